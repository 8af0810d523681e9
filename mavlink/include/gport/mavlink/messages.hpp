// The MAVLink codec's message table and typed encode/decode. The message
// structs and their field tables are in message_types.hpp; this header
// checks every table at compile time (wire order, CRC_EXTRA, members).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "gport/mavlink/fields.hpp"
#include "gport/mavlink/frame.hpp"
#include "gport/mavlink/message_types.hpp"
#include "gport/mavlink/result.hpp"

namespace gport::mavlink {

// ---- layout checks -------------------------------------------------------------

namespace detail {

using F = FieldType;

template <typename T>
struct FieldTypeOf;
template <>
struct FieldTypeOf<std::uint8_t> : std::integral_constant<F, F::kU8> {};
template <>
struct FieldTypeOf<std::int8_t> : std::integral_constant<F, F::kI8> {};
template <>
struct FieldTypeOf<std::uint16_t> : std::integral_constant<F, F::kU16> {};
template <>
struct FieldTypeOf<std::int16_t> : std::integral_constant<F, F::kI16> {};
template <>
struct FieldTypeOf<std::uint32_t> : std::integral_constant<F, F::kU32> {};
template <>
struct FieldTypeOf<std::int32_t> : std::integral_constant<F, F::kI32> {};
template <>
struct FieldTypeOf<std::uint64_t> : std::integral_constant<F, F::kU64> {};
template <>
struct FieldTypeOf<std::int64_t> : std::integral_constant<F, F::kI64> {};
template <>
struct FieldTypeOf<float> : std::integral_constant<F, F::kF32> {};
template <>
struct FieldTypeOf<double> : std::integral_constant<F, F::kF64> {};
template <>
struct FieldTypeOf<char> : std::integral_constant<F, F::kChar> {};

template <typename T>
struct Shape {
    static constexpr F type = FieldTypeOf<T>::value;
    static constexpr std::size_t count = 0;
};
template <typename T, std::size_t N>
struct Shape<std::array<T, N>> {
    static constexpr F type = FieldTypeOf<T>::value;
    static constexpr std::size_t count = N;
};

// True when M::visit() walks members of exactly the table's types, in order.
// (COMMAND_LONG's seven params are visited one by one, as scalars.)
template <typename M>
constexpr bool members_match_table() {
    M m{};
    std::size_t i = 0;
    bool ok = true;
    M::visit(m, [&](auto& member) {
        using S = Shape<std::remove_cvref_t<decltype(member)>>;
        ok = ok && i < M::kFields.size() && M::kFields[i].type == S::type &&
             M::kFields[i].count == S::count;
        ++i;
    });
    return ok && i == M::kFields.size();
}

template <typename M>
constexpr bool layout_ok() {
    return in_wire_order(M::kFields) && crc_extra_of(M::kName, M::kFields) == M::kCrcExtra &&
           members_match_table<M>() && full_length(M::kFields) <= kMaxPayloadSize;
}

}  // namespace detail

static_assert(detail::layout_ok<Heartbeat>());
static_assert(detail::layout_ok<CommandLong>());
static_assert(detail::layout_ok<CommandAck>());
static_assert(detail::layout_ok<GimbalDeviceInformation>());
static_assert(detail::layout_ok<GimbalDeviceSetAttitude>());
static_assert(detail::layout_ok<GimbalDeviceAttitudeStatus>());
static_assert(detail::layout_ok<AutopilotStateForGimbalDevice>());
static_assert(detail::layout_ok<Attitude>());
static_assert(detail::layout_ok<GlobalPositionInt>());
static_assert(detail::layout_ok<CameraInformation>());
static_assert(detail::layout_ok<CameraSettings>());
static_assert(detail::layout_ok<StorageInformation>());
static_assert(detail::layout_ok<CameraCaptureStatus>());
static_assert(detail::layout_ok<CameraImageCaptured>());
static_assert(detail::layout_ok<SystemTime>());
static_assert(detail::layout_ok<GpsRawInt>());
static_assert(full_length(GpsRawInt::kFields) == 52);
static_assert(full_length(CameraInformation::kFields) == 237);
static_assert(full_length(CameraImageCaptured::kFields) == 255);
static_assert(full_length(StorageInformation::kFields) == 61);
static_assert(full_length(CameraCaptureStatus::kFields) == 23);
static_assert(full_length(CameraSettings::kFields) == 14);

// ---- the message table ----------------------------------------------------------

struct MessageInfo {
    std::uint32_t id = 0;
    std::string_view name;
    std::uint8_t crc_extra = 0;
    std::size_t base_length = 0;  // payload bytes before the extensions
    std::size_t full_length = 0;  // payload bytes with them
};

// The table the decoder checks frames against; nullptr for an unknown id.
const MessageInfo* find_message(std::uint32_t id);
std::span<const MessageInfo> message_table();

// ---- strings ----------------------------------------------------------------------

// A char[N] field as text: up to the first NUL, or all N bytes.
template <std::size_t N>
std::string_view text_of(const Chars<N>& field) {
    std::size_t n = 0;
    while (n < N && field[n] != '\0') {
        ++n;
    }
    return {field.data(), n};
}

// Fills a char[N] field, NUL-padded; refuses text longer than N bytes.
template <std::size_t N>
Result<Chars<N>> chars_of(std::string_view text, std::string_view field) {
    if (text.size() > N) {
        return Error{std::string(field) + ": \"" + std::string(text) + "\" is " +
                     std::to_string(text.size()) + " bytes; at most " + std::to_string(N) + " fit"};
    }
    Chars<N> out{};
    for (std::size_t i = 0; i < text.size(); ++i) {
        out[i] = text[i];
    }
    return out;
}

// ---- codec ---------------------------------------------------------------------------

// The full-length payload of a message (no truncation), little-endian.
std::vector<std::uint8_t> payload_of(const Message& message);

// The message's id (its kId).
std::uint32_t id_of(const Message& message);
std::string_view name_of(const Message& message);

// A MAVLink 2 frame carrying the message, payload truncated of trailing
// zeros; with `signed_frame`, flagged signed with an empty signature block
// for a signer to fill (signing.hpp).
Frame encode(const Message& message, const Header& header, bool signed_frame = false);

// The typed message of a frame: the payload is zero-extended to the message's
// full length (truncated frames and senders with fewer extensions). Errors
// name the message id and what is wrong: an unknown id, or a payload longer
// than the message defines.
Result<Message> decode(const FrameView& frame);

// Bitwise equality (NaN equals the same NaN): the two payloads compared.
bool same_bits(const Message& a, const Message& b);

}  // namespace gport::mavlink

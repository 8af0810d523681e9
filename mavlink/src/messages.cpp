#include "gport/mavlink/messages.hpp"

#include <fmt/format.h>

#include <bit>
#include <vector>

namespace gport::mavlink {
namespace {

template <typename T>
constexpr bool is_array = false;
template <typename T, std::size_t N>
constexpr bool is_array<std::array<T, N>> = true;

// Appends one member, little-endian (floats by their IEEE-754 bits).
class Writer {
  public:
    template <typename T>
    void operator()(const T& value) {
        if constexpr (is_array<T>) {
            for (const auto& element : value) {
                (*this)(element);
            }
        } else if constexpr (std::is_floating_point_v<T>) {
            using Bits = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
            (*this)(std::bit_cast<Bits>(value));
        } else {
            using U = std::make_unsigned_t<T>;
            const auto bits = static_cast<U>(value);
            for (std::size_t i = 0; i < sizeof(T); ++i) {
                out.push_back(static_cast<std::uint8_t>((bits >> (8 * i)) & 0xFFU));
            }
        }
    }
    std::vector<std::uint8_t> out;
};

// Reads one member from a payload already zero-extended to full length.
class Reader {
  public:
    explicit Reader(std::span<const std::uint8_t> in) : in_(in) {}
    template <typename T>
    void operator()(T& value) {
        if constexpr (is_array<T>) {
            for (auto& element : value) {
                (*this)(element);
            }
        } else if constexpr (std::is_floating_point_v<T>) {
            using Bits = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
            Bits bits = 0;
            (*this)(bits);
            value = std::bit_cast<T>(bits);
        } else {
            using U = std::make_unsigned_t<T>;
            U bits = 0;
            for (std::size_t i = 0; i < sizeof(T); ++i) {
                bits =
                    static_cast<U>(bits | static_cast<U>(static_cast<U>(in_[pos_++]) << (8 * i)));
            }
            value = static_cast<T>(bits);
        }
    }

  private:
    std::span<const std::uint8_t> in_;
    std::size_t pos_ = 0;
};

template <typename M>
constexpr MessageInfo info_of() {
    return {M::kId, M::kName, M::kCrcExtra, base_length(M::kFields), full_length(M::kFields)};
}

template <typename... M>
constexpr auto make_table(std::variant<M...>*) {
    return std::array<MessageInfo, sizeof...(M)>{info_of<M>()...};
}

constexpr auto kTable = make_table(static_cast<Message*>(nullptr));

template <typename M>
Message read_as(std::span<const std::uint8_t> full) {
    M m{};
    M::visit(m, Reader(full));
    return m;
}

// One reader per alternative of Message, found by id.
template <typename... M>
Result<Message> read_by_id(std::uint32_t id, std::span<const std::uint8_t> full,
                           std::variant<M...>*) {
    Result<Message> out =
        Error{fmt::format("MAVLink message id {} is not one this codec decodes", id)};
    ((id == M::kId ? void(out = read_as<M>(full)) : void()), ...);
    return out;
}

}  // namespace

std::span<const MessageInfo> message_table() {
    return kTable;
}

const MessageInfo* find_message(std::uint32_t id) {
    for (const auto& info : kTable) {
        if (info.id == id) {
            return &info;
        }
    }
    return nullptr;
}

std::vector<std::uint8_t> payload_of(const Message& message) {
    return std::visit(
        [](const auto& m) {
            using M = std::remove_cvref_t<decltype(m)>;
            Writer w;
            M::visit(m, w);
            return std::move(w.out);
        },
        message);
}

std::uint32_t id_of(const Message& message) {
    return std::visit([](const auto& m) { return std::remove_cvref_t<decltype(m)>::kId; }, message);
}

std::string_view name_of(const Message& message) {
    return std::visit([](const auto& m) { return std::remove_cvref_t<decltype(m)>::kName; },
                      message);
}

Frame encode(const Message& message, const Header& header, bool signed_frame) {
    const MessageInfo* info = find_message(id_of(message));
    return Frame::make(header, info->id, info->crc_extra, payload_of(message), signed_frame);
}

Result<Message> decode(const FrameView& frame) {
    const MessageInfo* info = find_message(frame.msgid);
    if (info == nullptr) {
        return Error{
            fmt::format("MAVLink message id {} is not one this codec decodes "
                        "(HEARTBEAT, ATTITUDE, GLOBAL_POSITION_INT, COMMAND_LONG, "
                        "COMMAND_ACK, CAMERA_* 259-263, GIMBAL_DEVICE_* 283-285, "
                        "AUTOPILOT_STATE_FOR_GIMBAL_DEVICE)",
                        frame.msgid)};
    }
    if (frame.payload.size() > info->full_length) {
        return Error{fmt::format("MAVLink {} (id {}): payload of {} bytes; at most {}", info->name,
                                 info->id, frame.payload.size(), info->full_length)};
    }
    std::array<std::uint8_t, kMaxPayloadSize> full{};  // zero-extended
    std::copy(frame.payload.begin(), frame.payload.end(), full.begin());
    return read_by_id(frame.msgid, std::span(full).first(info->full_length),
                      static_cast<Message*>(nullptr));
}

bool same_bits(const Message& a, const Message& b) {
    return a.index() == b.index() && payload_of(a) == payload_of(b);
}

}  // namespace gport::mavlink

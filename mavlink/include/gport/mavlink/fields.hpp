// The field tables that drive the codec.
//
// Each message lists its fields in WIRE order: MAVLink 2 sorts the base
// fields by the size of their element type, largest first (stable, so equal
// sizes keep the order of the XML), then appends the extension fields in XML
// order, unsorted. The table gives the payload lengths and the CRC_EXTRA;
// messages.hpp checks at compile time that every table is in that order,
// that its CRC_EXTRA equals the value published with the definitions, and
// that the C++ struct visits the same fields with the same types.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "gport/mavlink/crc.hpp"

namespace gport::mavlink {

enum class FieldType : std::uint8_t {
    kU8,
    kI8,
    kU16,
    kI16,
    kU32,
    kI32,
    kU64,
    kI64,
    kF32,
    kF64,
    kChar
};

constexpr std::size_t element_size(FieldType t) {
    switch (t) {
        case FieldType::kU8:
        case FieldType::kI8:
        case FieldType::kChar:
            return 1;
        case FieldType::kU16:
        case FieldType::kI16:
            return 2;
        case FieldType::kU32:
        case FieldType::kI32:
        case FieldType::kF32:
            return 4;
        case FieldType::kU64:
        case FieldType::kI64:
        case FieldType::kF64:
            return 8;
    }
    return 0;
}

// The type's name as the XML writes it (the CRC_EXTRA digests these names;
// uint8_t_mavlink_version counts as uint8_t).
constexpr std::string_view type_name(FieldType t) {
    switch (t) {
        case FieldType::kU8:
            return "uint8_t";
        case FieldType::kI8:
            return "int8_t";
        case FieldType::kU16:
            return "uint16_t";
        case FieldType::kI16:
            return "int16_t";
        case FieldType::kU32:
            return "uint32_t";
        case FieldType::kI32:
            return "int32_t";
        case FieldType::kU64:
            return "uint64_t";
        case FieldType::kI64:
            return "int64_t";
        case FieldType::kF32:
            return "float";
        case FieldType::kF64:
            return "double";
        case FieldType::kChar:
            return "char";
    }
    return "";
}

struct FieldSpec {
    FieldType type = FieldType::kU8;
    std::string_view name;
    std::uint8_t count = 0;  // array length; 0 for a scalar
    bool extension = false;  // after <extensions/>: not sorted, not in CRC_EXTRA

    constexpr std::size_t size() const { return element_size(type) * (count == 0 ? 1 : count); }
};

// Bytes of the base fields (the MAVLink 1 length) and of all fields.
constexpr std::size_t base_length(std::span<const FieldSpec> fields) {
    std::size_t n = 0;
    for (const auto& f : fields) {
        n += f.extension ? 0 : f.size();
    }
    return n;
}

constexpr std::size_t full_length(std::span<const FieldSpec> fields) {
    std::size_t n = 0;
    for (const auto& f : fields) {
        n += f.size();
    }
    return n;
}

// True when the base fields are sorted by element size, largest first, and
// the extensions (if any) all come after them.
constexpr bool in_wire_order(std::span<const FieldSpec> fields) {
    bool in_extensions = false;
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].extension) {
            in_extensions = true;
            continue;
        }
        if (in_extensions) {
            return false;
        }
        if (i > 0 && element_size(fields[i].type) > element_size(fields[i - 1].type)) {
            return false;
        }
    }
    return true;
}

// CRC_EXTRA as the MAVLink generator computes it: X.25 over "NAME ", then
// for each base field in wire order "type " "name " and, for an array, one
// byte holding its length; the result's two bytes XORed together.
inline constexpr auto kSpace = static_cast<std::uint8_t>(' ');

constexpr std::uint8_t crc_extra_of(std::string_view message_name,
                                    std::span<const FieldSpec> fields) {
    std::uint16_t crc = crc_accumulate(message_name, kCrcInit);
    crc = crc_accumulate(kSpace, crc);
    for (const auto& f : fields) {
        if (f.extension) {
            continue;
        }
        crc = crc_accumulate(type_name(f.type), crc);
        crc = crc_accumulate(kSpace, crc);
        crc = crc_accumulate(f.name, crc);
        crc = crc_accumulate(kSpace, crc);
        if (f.count != 0) {
            crc = crc_accumulate(f.count, crc);
        }
    }
    return static_cast<std::uint8_t>((crc & 0xFFU) ^ (crc >> 8));
}

}  // namespace gport::mavlink

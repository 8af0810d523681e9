// Test-only tool for the node-mavlink cross-check (crosscheck.js):
//
//   mavlink_peer_tool emit STREAM EXPECTED.json
//       writes one MAVLink 2 frame of every sample message (samples.hpp) to
//       STREAM and their header and field values to EXPECTED.json;
//   mavlink_peer_tool decode STREAM
//       decodes STREAM with our decoder and prints the same JSON form, with
//       the decoder's counters, on stdout.
//
// JSON form: [{"name", "id", "seq", "sysid", "compid", "fields": {...}}],
// fields by their MAVLink (snake_case) names; 64-bit integers as decimal
// strings, NaN and infinities as "NaN", "Infinity", "-Infinity", char[N]
// as the text up to the first NUL.
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <vector>

#include "gport/mavlink/decoder.hpp"
#include "gport/mavlink/messages.hpp"
#include "samples.hpp"

namespace gm = gport::mavlink;
using nlohmann::json;

namespace {

json number(float v) {
    if (std::isnan(v)) {
        return "NaN";
    }
    if (std::isinf(v)) {
        return v > 0 ? "Infinity" : "-Infinity";
    }
    return static_cast<double>(v);
}

template <typename T>
json value_of(const T& v) {
    if constexpr (std::is_same_v<T, float>) {
        return number(v);
    } else if constexpr (sizeof(T) == 8) {
        return std::to_string(v);
    } else {
        return v;
    }
}

template <typename T, std::size_t N>
json value_of(const std::array<T, N>& v) {
    if constexpr (std::is_same_v<T, char>) {
        return std::string(gm::text_of(v));
    } else {
        json out = json::array();
        for (const auto& e : v) {
            out.push_back(value_of(e));
        }
        return out;
    }
}

json describe(const gm::Message& message, const gm::Header& header) {
    json fields = json::object();
    std::visit(
        [&](const auto& m) {
            using M = std::remove_cvref_t<decltype(m)>;
            std::size_t i = 0;
            M::visit(m, [&](const auto& member) {
                fields[std::string(M::kFields[i++].name)] = value_of(member);
            });
        },
        message);
    return {{"name", gm::name_of(message)}, {"id", gm::id_of(message)}, {"seq", header.seq},
            {"sysid", header.sysid},        {"compid", header.compid},  {"fields", fields}};
}

int emit(const std::string& stream_path, const std::string& json_path) {
    std::ofstream stream(stream_path, std::ios::binary);
    json all = json::array();
    std::uint8_t seq = 0;
    for (const auto& m : gport::mavlink::testing::sample_messages()) {
        const gm::Header header{seq, 42, gm::mav_comp_id::kGimbal};
        const gm::Frame frame = gm::encode(m, header);
        stream.write(reinterpret_cast<const char*>(frame.bytes().data()),
                     static_cast<std::streamsize>(frame.size()));
        all.push_back(describe(m, header));
        seq = static_cast<std::uint8_t>(seq + 1);
    }
    std::ofstream(json_path) << all.dump(2) << "\n";
    return stream && all.size() > 0 ? 0 : 1;
}

int decode(const std::string& stream_path) {
    std::ifstream in(stream_path, std::ios::binary);
    const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
    gm::Decoder decoder;
    json messages = json::array();
    int errors = 0;
    decoder.feed(bytes, [&](const gm::FrameView& view) {
        const auto m = gm::decode(view);
        if (!m) {
            std::cerr << m.error().message << "\n";
            ++errors;
            return;
        }
        messages.push_back(describe(*m, view.header));
    });
    const auto& s = decoder.stats();
    json out = {{"messages", messages},
                {"stats",
                 {{"bytes", s.bytes},
                  {"frames", s.frames},
                  {"garbage_bytes", s.garbage_bytes},
                  {"crc_errors", s.crc_errors},
                  {"length_errors", s.length_errors},
                  {"unknown_ids", s.unknown_ids},
                  {"unknown_bytes", s.unknown_bytes},
                  {"pending", decoder.pending()}}}};
    std::cout << out.dump(2) << "\n";
    return errors == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() == 3 && args[0] == "emit") {
        return emit(args[1], args[2]);
    }
    if (args.size() == 2 && args[0] == "decode") {
        return decode(args[1]);
    }
    std::cerr << "usage: mavlink_peer_tool emit STREAM EXPECTED.json | decode STREAM\n";
    return 64;
}

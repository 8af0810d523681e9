#include "gport/sim/recording.hpp"

#include <fmt/format.h>

#include <charconv>
#include <stdexcept>

#include "gport/base/hex.hpp"

namespace gport::sim {
namespace {

constexpr std::string_view kHeader = "# gport-sim recording v1";

protocol::Result<std::vector<std::uint8_t>> parse_hex(std::string_view hex) {
    if (hex.empty() || hex.size() % 2 != 0) {
        return protocol::Error{"hex bytes must be a non-empty, even number of digits"};
    }
    std::vector<std::uint8_t> bytes;
    bytes.reserve(hex.size() / 2);
    for (std::size_t i = 0; i < hex.size(); i += 2) {
        const int hi = base::hex_digit(hex[i]);
        const int lo = base::hex_digit(hex[i + 1]);
        if (hi < 0 || lo < 0) {
            return protocol::Error{fmt::format("'{}' is not a hex byte", hex.substr(i, 2))};
        }
        bytes.push_back(static_cast<std::uint8_t>(hi * 16 + lo));
    }
    return bytes;
}

// Splits off the next space-separated field.
std::string_view next_field(std::string_view& rest) {
    const auto start = rest.find_first_not_of(' ');
    if (start == std::string_view::npos) {
        rest = {};
        return {};
    }
    rest.remove_prefix(start);
    const auto end = rest.find(' ');
    const std::string_view field = rest.substr(0, end);
    rest.remove_prefix(end == std::string_view::npos ? rest.size() : end);
    return field;
}

}  // namespace

std::string format_record_line(const RecordEntry& e) {
    std::string line =
        fmt::format("{} {} ", std::chrono::duration_cast<std::chrono::microseconds>(e.t).count(),
                    e.direction == Direction::kRx ? "rx" : "tx");
    for (auto b : e.bytes) {
        line += fmt::format("{:02x}", b);
    }
    return line;
}

protocol::Result<RecordEntry> parse_record_line(std::string_view line) {
    std::string_view rest = line;
    const auto t = next_field(rest);
    const auto dir = next_field(rest);
    const auto hex = next_field(rest);
    if (!next_field(rest).empty() || hex.empty()) {
        return protocol::Error{"expected '<t_us> <rx|tx> <hex bytes>'"};
    }
    std::int64_t us = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), us);
    if (ec != std::errc{} || end != t.data() + t.size() || us < 0) {
        return protocol::Error{fmt::format("time '{}' is not a whole number of microseconds", t)};
    }
    if (dir != "rx" && dir != "tx") {
        return protocol::Error{fmt::format("direction '{}' is not rx or tx", dir)};
    }
    auto bytes = parse_hex(hex);
    if (!bytes) {
        return bytes.error();
    }
    return RecordEntry{std::chrono::microseconds(us), dir == "rx" ? Direction::kRx : Direction::kTx,
                       std::move(bytes).value()};
}

protocol::Result<std::vector<RecordEntry>> load_recording(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        return protocol::Error{fmt::format("cannot open recording '{}'", path)};
    }
    std::vector<RecordEntry> entries;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        if (line.empty() || line.front() == '#') {
            continue;
        }
        auto entry = parse_record_line(line);
        if (!entry) {
            return protocol::Error{fmt::format("{}:{}: {}", path, number, entry.error().message)};
        }
        if (!entries.empty() && entry->t < entries.back().t) {
            return protocol::Error{fmt::format("{}:{}: time goes backwards", path, number)};
        }
        entries.push_back(std::move(entry).value());
    }
    return entries;
}

Recorder::Recorder(const std::string& path) : path_(path), out_(path, std::ios::trunc) {
    if (!out_) {
        throw std::runtime_error(fmt::format("cannot create recording '{}'", path));
    }
    out_ << kHeader << '\n' << std::flush;
}

void Recorder::write(Duration t, Direction direction, std::span<const std::uint8_t> bytes) {
    if (bytes.empty()) {
        return;
    }
    out_ << format_record_line({t, direction, {bytes.begin(), bytes.end()}}) << '\n' << std::flush;
}

}  // namespace gport::sim

// CarryBuffer: feeds a byte-stream scanner across reads that cut frames
// anywhere. The scanner looks at a contiguous run of bytes and says how many
// it has dealt with (delivered or discarded); the rest, the start of a frame
// not yet complete, is carried into the next feed. The protocol decoders
// (G-Port, MAVLink) share it, so the chunking logic lives in one place.
//
// Input is scanned in place while nothing is carried; only a tail is copied.
// Capacity must hold two of the scanner's largest frames: a carried tail is
// always shorter than one frame, so every pass takes new bytes and the loop
// ends.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

namespace gport::base {

template <std::size_t Capacity>
class CarryBuffer {
  public:
    // scan(const std::uint8_t* p, std::size_t n) -> std::size_t used (<= n);
    // the n - used bytes left must be fewer than Capacity / 2.
    template <typename Scan>
    void feed(std::span<const std::uint8_t> input, Scan&& scan) {
        const std::uint8_t* in = input.data();
        std::size_t left = input.size();
        while (left > 0) {
            if (held_ == 0) {
                const std::size_t used = scan(in, left);
                held_ = left - used;
                std::memcpy(buffer_.data(), in + used, held_);
                return;
            }
            const std::size_t take = std::min(left, Capacity - held_);
            std::memcpy(buffer_.data() + held_, in, take);
            in += take;
            left -= take;
            const std::size_t total = held_ + take;
            const std::size_t used = scan(buffer_.data(), total);
            held_ = total - used;
            std::memmove(buffer_.data(), buffer_.data() + used, held_);
        }
    }

    // Bytes carried to the next feed.
    std::size_t held() const { return held_; }
    // Drops the carried bytes; returns how many there were.
    std::size_t clear() {
        const std::size_t dropped = held_;
        held_ = 0;
        return dropped;
    }

  private:
    std::array<std::uint8_t, Capacity> buffer_{};
    std::size_t held_ = 0;
};

}  // namespace gport::base

// The library's side of the shared-memory attitude channel: the mapping of
// gportd's block with a base::RingReader over it (AttitudeChannel::Impl),
// and RingWaker, which turns the ring's futex wakes into a pollable eventfd
// for Client::next_notification and AsyncClient (docs/client-cpp.md).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <thread>

#include "gport/base/attitude_ring.hpp"
#include "gport/client/attitude_channel.hpp"
#include "gport/client/types.hpp"

namespace gport::client {

struct AttitudeChannel::Impl {
    // Maps the memfd read-only and checks it; throws Error (kBadReply)
    // naming the problem. Does not close `fd`.
    static std::unique_ptr<Impl> map(int fd);
    // Claims the descriptor: maps it, then closes it (also on failure); -1
    // (the reply carried none) throws Error (kBadReply).
    static AttitudeChannel adopt(int fd);

    Impl(const void* block, std::size_t bytes) : memory(block), size(bytes), reader(block) {}
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
    ~Impl();

    // The next sample without waiting (see base::RingReader::next).
    std::optional<AttitudeSample> take();
    std::optional<AttitudeSample> next(std::chrono::milliseconds timeout);
    // From now on, take() gives only samples published after this call,
    // each of them (from sample 1 when none was published yet).
    void skip_to_newest() {
        cursor = reader.published();
        from_first = cursor == 0;
    }

    const void* memory;
    std::size_t size;
    base::RingReader reader;
    std::uint64_t cursor = 0;
    bool from_first = false;  // cursor 0 means "the newest" to RingReader
    std::atomic<std::uint64_t> missed{0};
};

// One thread per channel that sleeps on the ring's futex word and makes an
// eventfd readable whenever the word changed (a sample, or the close). The
// consumer polls fd(), calls reset() and then takes every sample there is.
// The eventfd starts readable, so the consumer looks once after making it.
// Costs the client one thread and one wake per sample; gportd does not know.
class RingWaker {
  public:
    explicit RingWaker(const base::RingReader& reader);
    RingWaker(const RingWaker&) = delete;
    RingWaker& operator=(const RingWaker&) = delete;
    ~RingWaker();

    int fd() const noexcept { return eventfd_; }
    void reset() noexcept;

  private:
    void run();

    const std::atomic<std::uint32_t>& word_;
    std::uint32_t seen_;
    int eventfd_ = -1;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

AttitudeSample to_attitude(const base::RingSample& sample, std::uint64_t dropped);

}  // namespace gport::client

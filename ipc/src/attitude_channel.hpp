// The daemon's end of the shared-memory attitude channel (docs/api.md,
// "Shared-memory attitude channel"): one sealed memfd holding a
// base::RingWriter ring, made on the first request and shared by every
// client that asks for it, and one wake block per connection that opened
// it (wake_block.hpp), whose futex word only that connection can wait on.
// The wakes themselves are made by a thread of their own (channel_waker.hpp),
// never on the event loop.
//
//   AttitudeChannel channel;
//   auto opened = channel.open_for(id);  // descriptors to send now (2 or 0), or why not
//   channel.descriptors(id);             // {ring, wake block}, with the reply's first byte
//   channel.delivered(id, error);        // 0: sent, its word is woken from now on;
//                                        // else they go with the next reply
//   channel.publish(sample);             // every 0x87 sample, then
//   channel.wake();                      // hands the waker thread a signal: O(1)
//   channel.forget(id);                  // closed: its block is never woken again
//   channel.close();                     // shutdown: closed flag, a last wake per reader,
//                                        // the thread joined
//
// The blocks are mapped read-write here and sealed afterwards (F_SEAL_SHRINK,
// F_SEAL_GROW, F_SEAL_FUTURE_WRITE, F_SEAL_SEAL): these mappings keep writing,
// while every other mapping of the descriptors can only be read-only.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <variant>

#include "channel_waker.hpp"
#include "gport/base/attitude_ring.hpp"
#include "gport/daemon/events.hpp"
#include "wake_block.hpp"

namespace gport::ipc::detail {

// The start of every -32603 message about the channel.
inline constexpr std::string_view kUnavailable = "attitude channel unavailable: ";

// The reply line to send instead when the descriptors could not be sent: the
// attitude_channel result in `line` that announced them ("descriptors" > 0)
// becomes -32603 with the same id, its message kUnavailable + `why`.
std::string unsent_reply(const std::string& line, const std::string& why);

// A sample as the ring carries it: the attitude notification's values.
base::RingSample ring_sample(const daemon::AttitudeSample& sample);

class AttitudeChannel {
  public:
    static constexpr std::uint32_t kSlots = 64;
    static constexpr std::size_t kBytes = base::ring_bytes(kSlots);
    // Descriptors sent with a connection's first attitude_channel result.
    static constexpr std::size_t kDescriptors = 2;

    AttitudeChannel() = default;
    ~AttitudeChannel();
    AttitudeChannel(const AttitudeChannel&) = delete;
    AttitudeChannel& operator=(const AttitudeChannel&) = delete;

    // Starts the waker thread and makes the ring the first time (later
    // calls do nothing). The error names the step that failed and why;
    // nothing is kept then, so the next call tries again.
    std::optional<std::string> open();

    // The ring, then connection `client`'s wake block (made on its first
    // request). Returns how many descriptors its reply carries: 2 when they
    // have not been sent (or queued) on this connection yet and the reply
    // will be sent (`deliver`), else 0; or the error when a block could not
    // be made.
    std::variant<std::size_t, std::string> open_for(std::uint64_t client, bool deliver = true);
    // {ring, wake block} for the reply being sent; -1s when `client` has no block.
    std::array<int, 2> descriptors(std::uint64_t client) const;
    // The reply carrying them went out (error 0: the waker wakes its word
    // from its next round on) or sendmsg refused it (errno): the next
    // request sends them again.
    void delivered(std::uint64_t client, int error);
    // The connection closed: its block is never bumped again once a round
    // under way has ended, and unmapped then.
    void forget(std::uint64_t client);
    // Connections that opened the channel.
    std::size_t readers() const { return readers_.size(); }
    bool has_reader(std::uint64_t client) const { return readers_.count(client) != 0; }

    // The ring's memfd (-1 before open()); it stays open until destruction.
    int fd() const { return fd_; }
    std::uint64_t published() const { return writer_ ? writer_->published() : 0; }

    // Writes one sample into the ring; nothing before open() or after close().
    void publish(const daemon::AttitudeSample& sample);
    // A new sample: the waker thread bumps each reader connection's word
    // and wakes one waiter on it, soon. Costs the loop O(1); nothing
    // without a reader.
    void wake();
    // No more samples: sets the closed flag, has every reader woken once
    // more and joins the waker thread. Idempotent.
    void close();
    // Every wake asked for so far has been made (for tests and benchmarks).
    bool wakes_done() const { return waker_.idle(); }

  private:
    enum class Delivery { kUnsent, kQueued, kSent };
    struct Reader {
        std::shared_ptr<WakeBlock> block;  // shared with the waker's snapshot
        Delivery delivery = Delivery::kUnsent;
    };

    // Hands the waker the blocks of every connection that has them.
    void update_waker();

    int fd_ = -1;
    void* memory_ = nullptr;
    std::optional<base::RingWriter> writer_;
    bool closed_ = false;
    std::unordered_map<std::uint64_t, Reader> readers_;
    std::size_t woken_readers_ = 0;  // readers whose descriptors were sent
    ChannelWaker waker_;             // last: joined before anything else goes
};

}  // namespace gport::ipc::detail

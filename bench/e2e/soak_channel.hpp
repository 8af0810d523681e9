// The soak's attacks on the shared-memory attitude channel (issue 22):
//   (f) futex waiters: a peer process parks threads on its connection's
//       wake word for the whole soak, and another parks threads and then
//       disconnects, keeping them parked (park_attack.hpp);
//   (g) descriptor hoarding: clients send batches of 32 attitude_channel
//       requests and never read;
// while a prober opens the channel on a fresh connection every few seconds:
// every probe must get its two descriptors ("descriptors":2), never
// -32603, and by the next probe its wake word must have moved if samples
// were published meanwhile. The prober never waits for a sample: it must
// not hold up the driver's loop (the settings floods react to the link).
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "park_attack.hpp"
#include "posix.hpp"

namespace gport::bench {

struct ChannelAttackOptions {
    std::string socket;
    int park_threads = 500;  // per parking peer (two peers)
    int hoarders = 4;
    int probe_every_ms = 2000;
};

class ChannelAttacks {
  public:
    explicit ChannelAttacks(ChannelAttackOptions o) : o_(std::move(o)) {}
    ~ChannelAttacks();

    void act(std::int64_t t_ns);
    void finish();

    std::vector<std::string> problems() const;
    nlohmann::json figures() const;

  private:
    // The last probe's connection and mappings, kept open until the next.
    struct Probe {
        Fd connection;
        const void* ring = nullptr;
        std::size_t ring_size = 0;
        const void* wake = nullptr;
        std::uint32_t word = 0;
        std::uint64_t published = 0;
        ~Probe();
    };

    void start(std::int64_t t_ns);
    // A hoarding connection and what it has still to send of its batch.
    struct Hoarder {
        Fd fd;
        std::string pending;
    };

    void hoard(std::int64_t t_ns);
    bool connect_hoarder(Hoarder& h);
    void probe();
    std::string open_probe();
    std::string check_last_probe();

    ChannelAttackOptions o_;
    bool started_ = false;
    std::vector<std::unique_ptr<ParkAttack>> parkers_;
    std::size_t parkers_started_ = 0;
    std::string park_error_;
    std::vector<Hoarder> hoarders_;
    std::int64_t next_hoard_ns_ = 0;
    std::uint64_t batches_ = 0;
    std::uint64_t hoard_refused_ = 0;    // new batches a full socket took nothing of
    std::uint64_t hoarders_closed_ = 0;  // connections gportd closed (each replaced)
    std::uint64_t hoard_rounds_ = 0;
    std::uint64_t hoard_rounds_idle_ = 0;  // rounds with no hoarder connection open
    std::string hoard_error_;              // the last failed connect
    std::int64_t next_probe_ns_ = 0;
    std::unique_ptr<Probe> last_probe_;
    std::uint64_t probes_ = 0;
    std::uint64_t probes_ok_ = 0;
    std::vector<std::string> probe_failures_;
};

}  // namespace gport::bench

// bench_e2e's command line.
#pragma once

#include <optional>
#include <string>

namespace gport::bench {

struct Options {
    double rate_hz = 200;             // 0x87 frames per second written to the pty
    int subscribers = 100;            // clients subscribed to attitude
    int shm_readers = 0;              // readers of the shared-memory attitude channel (--shm)
    int shm_threads = 0;              // threads they share (--shm-threads); 0 = one each
    bool subscriber_threads = false;  // one thread per socket subscriber (--subscriber-threads)
    int flooders = 0;                 // clients sending status requests back to back
    double seconds = 5;               // length of the measured stream
    double keepalive_hz = 10;         // the daemon's keepalive.rate_hz (default config)
    std::string gportd;               // the daemon binary
    std::string json_path;            // where to write the JSON summary ("" = nowhere)
    bool no_header = false;           // print only the table row
    int realtime_priority = 0;        // gportd's own realtime.priority (+ lock_memory); 0 = off
    bool daemon_fifo = false;         // run gportd SCHED_FIFO (diagnosis of scheduling delays)
    int stops = 0;                    // stop probe: motions ended by each cause (0 = off)
    int park_threads = 0;             // futex-waiter attack: threads parked by a peer (0 = off)
    bool park_gone = false;           // ... whose connection closed, plus one real holder
    int park_keys = 0;                // ... on this many keys of its own, not the wake word
    int stop_every_ms = 0;            // a commander sends `stop` this often (0 = off)
    std::string line_rate;            // --line-rate: scenarios at 115200 baud ("" = off)
    unsigned reader_uid = 0;          // --reader-uid: the read-only floods' uid (root only)
    double camera_rate = 0;  // --camera-rate: gportd's camera.max_commands_per_s (0: shipped)
    bool keep_logs = false;  // --keep-logs: leave each line-rate run's gportd log
    bool help = false;
};

// Parses argv; prints what was wrong and returns nullopt on a bad command line.
std::optional<Options> parse_options(int argc, char** argv);
std::string usage();

}  // namespace gport::bench

// The floods of the line-rate benchmark (bench_e2e --line-rate) and the
// soak's line-rate attacks: a process of its own (bench_e2e --flood-child)
// with N connections, each sending one request (or one batch) and waiting
// for its reply before the next, until it is killed. Run as root, it can
// drop to another uid first, so its connections are read-only peers.
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>

#include "process.hpp"

namespace gport::bench {

enum class FloodKind {
    kPhoto,     // `photo` with a 1 KiB meta
    kCaptures,  // `captures` limit 1000
    kBatches,   // batches of 32 `captures` limit 800
    kEvery,     // every read-only method in turn, batches included
    kVehicle,   // the trusted source gone wrong: publish_vehicle back to back
};

// "photo", "captures", "batches", "every", "vehicle"; false for anything else.
bool parse_flood_kind(const std::string& name, FloodKind& kind);
const char* to_string(FloodKind kind);

// A `meta` of about 1 KiB as compact JSON (under gportd's 1024-byte limit).
std::string kilobyte_meta();

class FloodProcess {
  public:
    // Starts `connections` connections of `kind` to `socket` as `uid` (0 =
    // stay as we are); throws std::runtime_error when the child cannot start
    // or reports that it could not connect.
    FloodProcess(const std::string& socket, FloodKind kind, int connections, uid_t uid);
    ~FloodProcess();
    FloodProcess(const FloodProcess&) = delete;
    FloodProcess& operator=(const FloodProcess&) = delete;
    // Kills the child (SIGKILL) and reaps it. Idempotent.
    void stop();

  private:
    std::unique_ptr<testing::Process> child_;
};

// bench_e2e --flood-child SOCKET KIND CONNECTIONS UID REPORT_FD
int flood_child_main(int argc, char** argv);

}  // namespace gport::bench

// Pseudo-terminal plumbing for the simulator: the master side it serves,
// the slave path a client opens, and the stable symlink to it.
#pragma once

#include <string>

namespace gport::sim {

struct PtyMaster {
    int fd = -1;             // non-blocking, close-on-exec; the caller owns it
    std::string slave_path;  // e.g. /dev/pts/7
};

// Creates a pty whose slave is already raw (no echo, no line editing, no
// CR/LF translation): the slave is opened once here, set with cfmakeraw and
// closed again before anyone else can open it. Leaving it closed also makes
// the master report POLLHUP until a client opens it, which is how the
// simulator knows nobody is listening. `access` sets the slave's group and
// mode as udev would a real adapter's (e.g. root:dialout 0660, so that an
// installed gportd, in group dialout, may open it). Throws std::system_error
// naming the failed call.
struct SlaveAccess {
    int gid = -1;       // the slave's group; -1: as devpts made it
    unsigned mode = 0;  // its permission bits; 0: as devpts made them
};
PtyMaster open_pty(const SlaveAccess& access = {});

// True while some process has the slave open (the master has no POLLHUP).
bool peer_present(int master_fd);

// What release_exclusive() found on the slave.
enum class Exclusivity {
    kNone,     // not in exclusive mode: anyone may open it
    kCleared,  // it was (TIOCEXCL); cleared with TIOCNXCL
    kStuck,    // it is, and the open to clear it was refused (EBUSY: no CAP_SYS_ADMIN)
};

// Clears the exclusive mode a client left on the slave once it has gone. On
// a pty the mode belongs to the slave's tty, which lives as long as the
// master is open, so it outlives the client (a killed gportd's TIOCEXCL
// would refuse every later open with EBUSY); a real serial port drops it on
// the last close. Opens the slave itself (non-blocking, briefly), so call it
// only while no client has it open. Only a process with CAP_SYS_ADMIN may
// open an exclusive tty: without it, the answer is kStuck and the pty must be
// replaced. Throws std::system_error for any other failure.
Exclusivity release_exclusive(const std::string& slave_path);

// A symlink at a fixed path to the current slave, as udev keeps
// /dev/serial/by-id/... for a USB adapter.
class SlaveLink {
  public:
    SlaveLink() = default;
    explicit SlaveLink(std::string path) : path_(std::move(path)) {}
    SlaveLink(const SlaveLink&) = delete;
    SlaveLink& operator=(const SlaveLink&) = delete;
    ~SlaveLink() { remove(); }

    const std::string& path() const { return path_; }
    // Points the link at `target`, replacing an older symlink atomically.
    // Refuses (std::system_error) to replace anything that is not a symlink.
    void point_to(const std::string& target);
    // Removes the link if it still points where we put it.
    void remove() noexcept;

  private:
    std::string path_;
    std::string target_;
};

}  // namespace gport::sim

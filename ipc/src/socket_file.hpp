// The socket's file on disk: stale-file removal, mode and group.
#pragma once

#include <string>

namespace gport::ipc::detail {

// Makes `path` free for bind(): removes a stale socket (nobody answers a
// connect), refuses with std::runtime_error when a daemon answers there or
// when the path is something other than a socket.
void clear_stale_socket(const std::string& path);

// chmod to `mode`, and chown to `group` (by name) unless it is empty.
void apply_mode_and_group(const std::string& path, unsigned mode, const std::string& group);

}  // namespace gport::ipc::detail

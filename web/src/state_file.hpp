// gport-web's own small files beside its token file (docs/web.md, "Logging
// in at the field"): the sessions and the login codes used, kept across a
// restart. Read only when the file is a regular file of ours that no one
// else can read (never through a symlink); written whole to a temporary
// file, mode 0600, then renamed over it.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace gport::web {

// The file's lines; empty when it does not exist; nullopt (with `problem`
// set) when it is not one gport-web may trust.
std::optional<std::vector<std::string>> read_state_file(const std::string& path,
                                                        std::string& problem);
// Replaces the file with these lines; false (with `problem`) on failure.
bool write_state_file(const std::string& path, const std::vector<std::string>& lines,
                      std::string& problem);

}  // namespace gport::web

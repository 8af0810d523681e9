// The layout of the config file: which sections and keys exist, how each
// value is checked, and the checks between keys of one section.
#pragma once

#include "gport/config/config.hpp"
#include "reader.hpp"

namespace gport::config::detail {

// Reads the parsed file `root` on top of the values already in `config`,
// recording every problem in `reader`.
void read_config(Reader& reader, const Json& root, Config& config);

}  // namespace gport::config::detail

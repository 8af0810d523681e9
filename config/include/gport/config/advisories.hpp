// Configurations that are valid but probably not what the operator meant:
// gportd runs them and says so, once, at start and after each reload
// (docs/configuration.md, "Warnings").
#pragma once

#include <string>
#include <vector>

#include "gport/config/config.hpp"

namespace gport::config {

// One line per surprise, naming the keys involved and what gportd will do;
// empty for a configuration without any.
std::vector<std::string> advisories(const Config& config);

}  // namespace gport::config

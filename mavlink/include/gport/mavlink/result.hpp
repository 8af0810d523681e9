// The MAVLink codec's failures: bytes off the network and values that users
// control return a Result whose error is a message.
#pragma once

#include <string>

#include "gport/base/result.hpp"

namespace gport::mavlink {

struct Error {
    std::string message;
};

template <typename T>
using Result = gport::Result<T, Error>;

}  // namespace gport::mavlink

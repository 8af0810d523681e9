// The protocol layer's failures: input that users control (angles, speeds,
// frames off the wire) returns a Result whose error is a message.
// Programming errors throw.
#pragma once

#include <string>

#include "gport/base/result.hpp"

namespace gport::protocol {

struct Error {
    std::string message;
};

template <typename T>
using Result = gport::Result<T, Error>;

}  // namespace gport::protocol

// A value or every problem found in the input that should have produced it.
//
// Configuration is fixed by a person editing a file, so the loader reports all
// problems at once (one message each) instead of stopping at the first one.
#pragma once

#include <string>
#include <vector>

#include "gport/base/result.hpp"

namespace gport::config {

// One message per problem; each names the key or option and what is allowed.
// A failed Result always carries at least one.
struct Errors {
    std::vector<std::string> messages;

    // The messages one per line, ready to print to stderr or the journal.
    std::string text() const {
        std::string all;
        for (const auto& message : messages) {
            all += message;
            all += '\n';
        }
        return all;
    }
};

template <typename T>
using Result = gport::Result<T, Errors>;

}  // namespace gport::config

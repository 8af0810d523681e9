// gport_ring_read (ring_read.h): base::ring_read_words for C callers.
#include "gport/client/ring_read.h"

#include <array>
#include <cstring>

#include "gport/base/attitude_ring.hpp"

extern "C" int gport_ring_read(const void* block, uint32_t slot_count, uint64_t n,
                               uint64_t words[15]) {
    if (block == nullptr || words == nullptr) {
        return 0;
    }
    std::array<std::uint64_t, gport::base::kRingSampleWords> read{};
    if (!gport::base::ring_read_words(block, slot_count, n, read)) {
        return 0;
    }
    std::memcpy(words, read.data(), sizeof(read));
    return 1;
}

extern "C" uint32_t gport_client_abi_minor(void) {
    return 2;
}

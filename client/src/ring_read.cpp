// The C interface (ring_read.h): base::RingReader's reads for C callers.
// Each function reads one layout version, fixed by the checks below: a new
// layout of base/ fails the build here until it gets functions of its own.
#include "gport/client/ring_read.h"

#include <array>
#include <cstring>

#include "gport/base/attitude_ring.hpp"
#include "gport/base/wake_block.hpp"

namespace base = gport::base;

static_assert(base::kRingVersion == GPORT_RING_LAYOUT_VERSION,
              "the ring's layout changed: give the C interface new functions for it");
static_assert(base::kWakeVersion == GPORT_WAKE_BLOCK_VERSION,
              "the wake block's layout changed: give the C interface new functions for it");
static_assert(base::kRingSampleWords == GPORT_RING_SAMPLE_WORDS);
static_assert(base::kRingFlagClosed == GPORT_RING_FLAG_CLOSED);

extern "C" int gport_ring_read(const void* ring, uint32_t slot_count, uint64_t n,
                               uint64_t words[GPORT_RING_SAMPLE_WORDS]) {
    if (ring == nullptr || words == nullptr) {
        return 0;
    }
    std::array<std::uint64_t, base::kRingSampleWords> read{};
    if (!base::ring_read_words(ring, slot_count, n, read)) {
        return 0;
    }
    std::memcpy(words, read.data(), sizeof(read));
    return 1;
}

extern "C" uint64_t gport_ring_published(const void* ring) {
    return ring == nullptr ? 0
                           : static_cast<const base::RingHeader*>(ring)->published.load(
                                 std::memory_order_acquire);
}

extern "C" uint32_t gport_ring_flags(const void* ring) {
    return ring == nullptr
               ? 0
               : static_cast<const base::RingHeader*>(ring)->flags.load(std::memory_order_acquire);
}

extern "C" uint32_t gport_wake_word(const void* wake_block) {
    return wake_block == nullptr ? 0 : base::wake_word(wake_block).load(std::memory_order_acquire);
}

extern "C" uint32_t gport_client_abi_minor(void) {
    return GPORT_CLIENT_MINOR;  // from client/CMakeLists.txt's GPORT_CLIENT_VERSION
}

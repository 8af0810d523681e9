/* The C entry point of libgport-client for readers of gportd's shared-memory
 * attitude ring written in other languages (the Python client loads it with
 * ctypes; docs/client-python.md). It is the seqlock read of
 * base::RingReader, with the C++ memory-model fences a weakly ordered CPU
 * (arm64) needs: a language that can only make plain loads cannot tell a
 * torn sample from a whole one there.
 *
 * Since libgport-client 1.2.0 (SONAME libgport-client.so.1). */
#ifndef GPORT_CLIENT_RING_READ_H
#define GPORT_CLIENT_RING_READ_H

#include <stdint.h>

#include "gport/client/export.hpp"

#ifdef __cplusplus
extern "C" {
#endif

/* Reads sample n (1, 2, ...) of the ring mapped at `block` (the whole block,
 * ring layout version 2, docs/api.md), whose slot count the caller checked
 * (`slot_count`, never re-read from the block). On success fills the 15
 * words of the slot after its seq (sample seq, t, imu roll/pitch/yaw, hall
 * roll/pitch/yaw, has_rates, hall rates, imu rates x/y/z; doubles as their
 * bit patterns) and returns 1; returns 0 when sample n is not in the ring,
 * is being written or was overwritten while read (words are then
 * unspecified), or when block or words is NULL or slot_count is 0. */
GPORT_CLIENT_API int gport_ring_read(const void* block, uint32_t slot_count, uint64_t n,
                                     uint64_t words[15]);

/* 1.2 for libgport-client 1.2.x: lets a loader check what it found. */
GPORT_CLIENT_API uint32_t gport_client_abi_minor(void);

#ifdef __cplusplus
}
#endif

#endif

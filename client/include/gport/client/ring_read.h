/* libgport-client's C interface: the reads of gportd's shared-memory
 * attitude channel for readers written in other languages (the Python
 * client loads it with ctypes; docs/client-python.md). They are the reads
 * of base::RingReader, with the C++ memory-model fences and acquire loads a
 * weakly ordered CPU (arm64) needs: a language that can only make plain
 * loads cannot tell a torn sample from a whole one there, nor order its
 * look at the wake word before its look at `published`.
 *
 * A C header (C99 or later, and C++), standalone.
 *
 * Layouts: every function here reads the ring of layout version 2 and the
 * wake block of version 1 (docs/api.md, "Shared-memory attitude channel";
 * GPORT_RING_LAYOUT_VERSION, GPORT_WAKE_BLOCK_VERSION), mapped whole, whose
 * headers (magic, version, sizes) and slot count the caller checked. That
 * is part of their contract in every libgport-client.so.1: a later layout
 * comes with functions of other names, never behind these.
 *
 * Versions (gport_client_abi_minor): gport_ring_read and
 * gport_client_abi_minor since 1.2; gport_ring_published, gport_ring_flags
 * and gport_wake_word since 1.3. A program that loads the library at run
 * time (dlopen, ctypes) checks gport_client_abi_minor() first. */
#ifndef GPORT_CLIENT_RING_READ_H
#define GPORT_CLIENT_RING_READ_H

#include <stdint.h>

#if defined(__GNUC__)
#define GPORT_CLIENT_C_API __attribute__((visibility("default")))
#else
#define GPORT_CLIENT_C_API
#endif

#define GPORT_RING_LAYOUT_VERSION 2
#define GPORT_WAKE_BLOCK_VERSION 1
/* The words of a sample after its slot's seq. */
#define GPORT_RING_SAMPLE_WORDS 15
/* gport_ring_flags: gportd stopped publishing (it is shutting down). */
#define GPORT_RING_FLAG_CLOSED 1u

#ifdef __cplusplus
extern "C" {
#endif

/* Reads sample n (1, 2, ...) of the ring at `ring`, whose slot count the
 * caller checked (`slot_count`, never re-read from the block). On success
 * fills the 15 words of the slot after its seq (sample seq, t, imu
 * roll/pitch/yaw, hall roll/pitch/yaw, has_rates, hall rates, imu rates
 * x/y/z; doubles as their bit patterns) and returns 1; returns 0 when
 * sample n is not in the ring, is being written or was overwritten while
 * read (words are then unspecified), or when ring or words is NULL or
 * slot_count is 0. Since 1.2. */
GPORT_CLIENT_C_API int gport_ring_read(const void* ring, uint32_t slot_count, uint64_t n,
                                       uint64_t words[GPORT_RING_SAMPLE_WORDS]);

/* The ring's `published` (the number of the newest sample; 0 before the
 * first), an acquire load: the samples it counts are visible to the reads
 * that follow. 0 for NULL. Since 1.3. */
GPORT_CLIENT_C_API uint64_t gport_ring_published(const void* ring);

/* The ring's flags (GPORT_RING_FLAG_CLOSED), an acquire load: once the
 * closed flag is seen, so is every sample published before it. 0 for NULL.
 * Since 1.3. */
GPORT_CLIENT_C_API uint32_t gport_ring_flags(const void* ring);

/* The futex word of the connection's wake block at `wake_block`, an
 * acquire load: read it before looking for samples, and wait on the value
 * read (FUTEX_WAIT on wake_block + 16); gportd bumps it after publishing.
 * 0 for NULL. Since 1.3. */
GPORT_CLIENT_C_API uint32_t gport_wake_word(const void* wake_block);

/* The minor version of this libgport-client.so.1: 3 for 1.3.x. A loader
 * needs at least the minor that added each function it calls. Since 1.2. */
GPORT_CLIENT_C_API uint32_t gport_client_abi_minor(void);

#ifdef __cplusplus
}
#endif

#endif

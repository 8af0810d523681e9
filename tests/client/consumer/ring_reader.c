/* A C program outside the tree, built against the installed
 * libgport-client with a C compiler: ring_read.h is a standalone C header,
 * and its functions are exported. */
#include <gport/client/ring_read.h>
#include <stdio.h>

#if GPORT_RING_LAYOUT_VERSION != 2 || GPORT_WAKE_BLOCK_VERSION != 1
#error "unexpected layout versions"
#endif

int main(void) {
    uint64_t words[GPORT_RING_SAMPLE_WORDS] = {0};
    const uint32_t minor = gport_client_abi_minor();
    if (minor < 3) {
        fprintf(stderr, "gport_client_abi_minor() = %u, expected 3 or more\n", (unsigned)minor);
        return 1;
    }
    if (gport_ring_read(NULL, 64, 1, words) != 0 || gport_ring_published(NULL) != 0 ||
        gport_ring_flags(NULL) != 0 || gport_wake_word(NULL) != 0) {
        fprintf(stderr, "a NULL block did not read as nothing\n");
        return 1;
    }
    printf("ok: libgport-client 1.%u\n", (unsigned)minor);
    return 0;
}

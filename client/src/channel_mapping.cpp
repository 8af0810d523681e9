// Checking, mapping and claiming the attitude channel's blocks: nothing a
// server sends is trusted (a descriptor that is not a sealed memfd of the
// announced size is refused before it is mapped, so no block can shrink
// under this process and kill it with SIGBUS, and every size the reader
// uses is the one checked here, never re-read from shared memory).
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "codec.hpp"
#include "gport/base/descriptors.hpp"
#include "gport/base/wake_block.hpp"
#include "gport/client/error.hpp"
#include "ring_channel.hpp"

namespace gport::client {
namespace {

Error channel_error(const std::string& what) {
    return Error(ErrorCode::kBadReply, "attitude channel: " + what);
}

std::string hex(unsigned value) {
    char text[16];
    std::snprintf(text, sizeof(text), "0x%x", value);
    return text;
}

// A descriptor is used only when it is a memfd that can neither shrink nor
// be written through a new mapping, and of exactly `size` bytes. The seals
// are read first: once F_SEAL_SHRINK is there nobody can remove it, so the
// size seen next stays. (Size first, a server holding another descriptor
// could shrink the file between the two looks and seal it then: the client
// would map the old size and die of SIGBUS.)
void check_descriptor(int fd, std::size_t size, const char* what) {
    const int seals = ::fcntl(fd, F_GET_SEALS);
    if (seals < 0) {
        throw channel_error(std::string("the ") + what +
                            " is not a sealed memfd (F_GET_SEALS: " + std::strerror(errno) + ")");
    }
    const unsigned have = static_cast<unsigned>(seals);
    if ((have & F_SEAL_SHRINK) == 0 || (have & (F_SEAL_WRITE | F_SEAL_FUTURE_WRITE)) == 0) {
        throw channel_error(std::string("the ") + what + " is not sealed against shrinking and " +
                            "writing (seals " + hex(have) +
                            "; F_SEAL_SHRINK and F_SEAL_WRITE or F_SEAL_FUTURE_WRITE are "
                            "required): refused");
    }
    struct stat info {};
    if (::fstat(fd, &info) != 0) {
        throw channel_error(std::string("cannot examine the ") + what + ": " +
                            std::strerror(errno));
    }
    if (!S_ISREG(info.st_mode) || info.st_size < 0 ||
        static_cast<std::size_t>(info.st_size) != size) {
        throw channel_error(std::string("the ") + what + " is " + std::to_string(info.st_size) +
                            " bytes, not the " + std::to_string(size) + " expected");
    }
}

const void* map_read_only(int fd, std::size_t size, const char* what) {
    void* memory = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
    if (memory == MAP_FAILED) {
        throw channel_error(std::string("cannot map the ") + what + ": " + std::strerror(errno));
    }
    return memory;
}

std::uint64_t unsigned_member(const nlohmann::json& result, const char* name) {
    const auto it = result.find(name);
    if (it == result.end() || !it->is_number_unsigned()) {
        throw channel_error(std::string("the reply's \"") + name +
                            "\" is missing or not a non-negative integer");
    }
    return it->get<std::uint64_t>();
}

}  // namespace

ChannelReply ChannelReply::parse(const nlohmann::json& result) {
    if (!result.is_object()) {
        throw channel_error("the reply's result is not an object");
    }
    const auto version = unsigned_member(result, "version");
    if (version != base::kRingVersion) {
        throw channel_error("gportd's channel is version " + std::to_string(version) +
                            "; this library reads version " + std::to_string(base::kRingVersion) +
                            " (update " +
                            (version < base::kRingVersion ? "gportd" : "the library") + ")");
    }
    ChannelReply r;
    const auto slots = unsigned_member(result, "slots");
    if (slots == 0 || (slots & (slots - 1)) != 0 || slots > base::kRingMaxSlots) {
        throw channel_error("slots = " + std::to_string(slots) +
                            " is not a power of two from 1 to " +
                            std::to_string(base::kRingMaxSlots));
    }
    r.slots = static_cast<std::uint32_t>(slots);
    r.size = unsigned_member(result, "size");
    if (r.size != base::ring_bytes(r.slots)) {
        throw channel_error("size = " + std::to_string(r.size) + " does not fit " +
                            std::to_string(slots) + " slots (" +
                            std::to_string(base::ring_bytes(r.slots)) + " bytes)");
    }
    r.descriptors = unsigned_member(result, "descriptors");
    if (r.descriptors != 0 && r.descriptors != 2) {
        throw channel_error("descriptors = " + std::to_string(r.descriptors) +
                            "; gportd sends 2 or 0");
    }
    return r;
}

std::shared_ptr<ChannelMapping> ChannelMapping::map(int ring_fd, int wake_fd,
                                                    const ChannelReply& reply) {
    check_descriptor(ring_fd, reply.size, "ring");
    check_descriptor(wake_fd, base::kWakeBlockBytes, "wake block");
    const void* ring = map_read_only(ring_fd, reply.size, "ring");
    const void* wake = nullptr;
    try {
        wake = map_read_only(wake_fd, base::kWakeBlockBytes, "wake block");
        if (auto problem = base::RingReader::check(ring, reply.size)) {
            throw channel_error(*problem);
        }
        if (base::RingReader::slots_in(reply.size) != reply.slots) {
            throw channel_error("the ring does not hold the slots the reply announced");
        }
        if (auto problem = base::check_wake_block(wake, base::kWakeBlockBytes)) {
            throw channel_error(*problem);
        }
    } catch (...) {
        ::munmap(const_cast<void*>(ring), reply.size);
        if (wake != nullptr) {
            ::munmap(const_cast<void*>(wake), base::kWakeBlockBytes);
        }
        throw;
    }
    return std::shared_ptr<ChannelMapping>(new ChannelMapping(ring, reply.size, wake));
}

ChannelMapping::ChannelMapping(const void* ring, std::size_t ring_size, const void* wake)
    : ring_(ring),
      ring_size_(ring_size),
      wake_(wake),
      reader_(ring, ring_size),
      word_(&base::wake_word(wake)),
      relayed_(word_->load(std::memory_order_acquire)) {}

ChannelMapping::~ChannelMapping() {
    ::munmap(const_cast<void*>(ring_), ring_size_);
    ::munmap(const_cast<void*>(wake_), base::kWakeBlockBytes);
}

// The word changes once per sample and once at the close; gportd wakes one
// waiter per change. The first thread to see a change (whichever: woken by
// gportd, by a timeout or just arriving) wakes all the others, once. Keyed
// on the word rather than on `published`: a thread may see a sample before
// gportd's bump, and the thread gportd then wakes must still pass it on.
void ChannelMapping::relay(std::uint32_t seen) {
    if (relayed_.claim(seen)) {  // only forward (WakeRelay)
        base::futex_wake_all(*word_);
    }
}

AttitudeChannel claim_channel(const nlohmann::json& reply, std::deque<int>& fds,
                              std::shared_ptr<ChannelMapping>& cache) {
    const auto& result = codec::result_of(reply);  // gportd's error: thrown as it is
    const auto parsed = ChannelReply::parse(result);
    if (parsed.descriptors == 0) {
        if (!cache) {
            throw channel_error(
                "gportd sent no descriptors (\"descriptors\":0: this connection should have "
                "them already) and this connection has none; reconnect to get them");
        }
        return AttitudeChannel(std::make_unique<AttitudeChannel::Impl>(cache));
    }
    if (fds.size() < 2) {
        throw channel_error("gportd's reply carried " + std::to_string(fds.size()) +
                            " file descriptor(s), not the 2 it announced");
    }
    const int ring = base::take_descriptor(fds);
    const int wake = base::take_descriptor(fds);
    try {
        cache = ChannelMapping::map(ring, wake, parsed);
    } catch (...) {
        ::close(ring);
        ::close(wake);
        throw;
    }
    ::close(ring);
    ::close(wake);
    return AttitudeChannel(std::make_unique<AttitudeChannel::Impl>(cache));
}

}  // namespace gport::client

#include "wake_block.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "gport/base/futex.hpp"

namespace gport::ipc::detail {
namespace {

constexpr unsigned kWakeSeals = F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE | F_SEAL_SEAL;

std::string wake_failed(const char* step) {
    return std::string(step) + ": " + std::strerror(errno);
}

}  // namespace

std::variant<std::unique_ptr<WakeBlock>, std::string> WakeBlock::make() {
    const int fd = ::memfd_create("gportd-wake", MFD_CLOEXEC | MFD_ALLOW_SEALING);
    if (fd < 0) {
        return wake_failed("memfd_create (wake block)");
    }
    if (::ftruncate(fd, static_cast<off_t>(base::kWakeBlockBytes)) != 0) {
        auto error = wake_failed("ftruncate (wake block)");
        ::close(fd);
        return error;
    }
    void* memory =
        ::mmap(nullptr, base::kWakeBlockBytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (memory == MAP_FAILED) {
        auto error = wake_failed("mmap (wake block)");
        ::close(fd);
        return error;
    }
    base::format_wake_block(memory);
    if (::fcntl(fd, F_ADD_SEALS, kWakeSeals) != 0) {
        auto error = wake_failed("sealing the wake block");
        ::munmap(memory, base::kWakeBlockBytes);
        ::close(fd);
        return error;
    }
    return std::unique_ptr<WakeBlock>(new WakeBlock(fd, memory));
}

WakeBlock::WakeBlock(int fd, void* memory)
    : fd_(fd), memory_(memory), block_(static_cast<base::WakeBlock*>(memory)) {}

WakeBlock::~WakeBlock() {
    ::munmap(memory_, base::kWakeBlockBytes);
    forget_descriptor();
}

void WakeBlock::forget_descriptor() {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
}

long WakeBlock::bump_and_wake() const {
    block_->wake.fetch_add(1, std::memory_order_release);
    return base::futex_wake(block_->wake, 1);
}

}  // namespace gport::ipc::detail

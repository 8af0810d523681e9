// Test helpers: put a file descriptor in place of a fixed one (fd 2, fd 3,
// ...) for the duration of a test, and set environment variables, restoring
// both afterwards.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cstdlib>
#include <optional>
#include <string>

namespace gport::systemd::test {

// Makes `target` a duplicate of `source` until destroyed, then restores
// whatever `target` was before (or closes it if it was not open).
class FdOverride {
  public:
    FdOverride(int target, int source) : target_(target) {
        if (fcntl(target_, F_GETFD) != -1) {
            saved_ = fcntl(target_, F_DUPFD_CLOEXEC, 100);
        }
        dup2(source, target_);
    }
    ~FdOverride() {
        if (saved_ >= 0) {
            dup2(saved_, target_);
            close(saved_);
        } else {
            close(target_);
        }
    }
    FdOverride(const FdOverride&) = delete;
    FdOverride& operator=(const FdOverride&) = delete;

  private:
    int target_;
    // -1: `target` was not open. (A std::optional<int> here made g++ 12 at
    // -O1 warn "may be used uninitialized" in a plain build: a false
    // positive, with -Werror an error.)
    int saved_ = -1;
};

// Sets (or, with std::nullopt, unsets) an environment variable until
// destroyed, then restores its previous value.
class EnvOverride {
  public:
    EnvOverride(std::string name, const std::optional<std::string>& value)
        : name_(std::move(name)) {
        if (const char* old = std::getenv(name_.c_str())) {
            saved_ = old;
        }
        apply(value);
    }
    ~EnvOverride() { apply(saved_); }
    EnvOverride(const EnvOverride&) = delete;
    EnvOverride& operator=(const EnvOverride&) = delete;

  private:
    void apply(const std::optional<std::string>& value) {
        if (value) {
            setenv(name_.c_str(), value->c_str(), 1);
        } else {
            unsetenv(name_.c_str());
        }
    }

    std::string name_;
    std::optional<std::string> saved_;
};

// A temporary file, removed when destroyed; `fd` is open for reading and writing.
class TempFile {
  public:
    TempFile() {
        std::string pattern = "/tmp/gport-systemd-test-XXXXXX";
        fd = mkstemp(pattern.data());
        path = pattern;
    }
    ~TempFile() {
        close(fd);
        unlink(path.c_str());
    }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;

    // Everything written to the file so far.
    [[nodiscard]] std::string contents() const {
        std::string text;
        char buffer[4096];
        for (off_t offset = 0;;) {
            const ssize_t n = pread(fd, buffer, sizeof buffer, offset);
            if (n <= 0) {
                return text;
            }
            text.append(buffer, static_cast<std::size_t>(n));
            offset += n;
        }
    }

    int fd = -1;
    std::string path;
};

}  // namespace gport::systemd::test

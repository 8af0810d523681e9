#include "gport/web/tokens.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace gport::web {
namespace {

constexpr std::size_t kMinTokenLength = 16;

bool token_char(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) {
        s.remove_prefix(1);
    }
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
        s.remove_suffix(1);
    }
    return s;
}

Token token_of(std::string_view line, int number) {
    Token token;
    if (line.starts_with("control:")) {
        line.remove_prefix(8);
    } else if (line.starts_with("view:")) {
        line.remove_prefix(5);
        token.role = Role::kView;
    }
    bool valid = line.size() >= kMinTokenLength;
    for (char c : line) {
        valid = valid && token_char(c);
    }
    if (!valid) {
        throw std::runtime_error("line " + std::to_string(number) +
                                 ": a token is at least 16 characters from [A-Za-z0-9_-], "
                                 "optionally after control: or view:");
    }
    token.secret = std::string(line);
    return token;
}

// A token given twice (as control: and as view:, or twice alike) is
// refused: which role it grants would depend on the order of the lines.
void refuse_repeated(const std::vector<Token>& tokens, int number) {
    const auto& added = tokens.back();
    for (std::size_t i = 0; i + 1 < tokens.size(); ++i) {
        if (tokens[i].secret == added.secret) {
            throw std::runtime_error("line " + std::to_string(number) +
                                     ": the same token as an earlier line (as " +
                                     std::string(role_name(tokens[i].role)) +
                                     "): each token appears once, with one role");
        }
    }
}

std::string mode_text(mode_t mode) {
    char text[8];
    std::snprintf(text, sizeof(text), "%04o", static_cast<unsigned>(mode & 07777));
    return text;
}

std::string errno_text() {
    return std::strerror(errno);
}

// Makes the missing directories above the file, each 0700 (gport-web's
// alone: a directory made for a secret is no one else's to list).
void make_parents(const std::filesystem::path& dir) {
    if (dir.empty() || std::filesystem::exists(dir)) {
        return;
    }
    make_parents(dir.parent_path());
    if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST) {
        throw std::runtime_error("cannot create " + dir.string() + ": " + errno_text());
    }
}

// Creates the file with a new control token; false when it appeared meanwhile.
bool create(const std::string& path, const std::string& secret) {
    make_parents(std::filesystem::path(path).parent_path());
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) {
        if (errno == EEXIST) {
            return false;
        }
        throw std::runtime_error("cannot create the token file: " + errno_text());
    }
    const std::string text = "control:" + secret + "\n";
    const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
    ::close(fd);
    if (!written) {
        throw std::runtime_error("cannot write the token file");
    }
    return true;
}

std::string read_checked(const std::string& path) {
    // O_NONBLOCK: a FIFO put in its place opens at once (and is refused
    // below as no regular file) instead of waiting for a writer forever.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd < 0) {
        throw std::runtime_error("cannot open it: " + errno_text());
    }
    struct stat st {};
    ::fstat(fd, &st);
    if (!S_ISREG(st.st_mode) || st.st_uid != ::geteuid() || (st.st_mode & 077) != 0) {
        ::close(fd);
        throw std::runtime_error("it must be a regular file of user " +
                                 std::to_string(::geteuid()) +
                                 " readable by no one else (mode 0600 or 0400); it has mode " +
                                 mode_text(st.st_mode) + " and owner " + std::to_string(st.st_uid));
    }
    std::string text;
    char chunk[4096];
    ssize_t n;
    while ((n = ::read(fd, chunk, sizeof(chunk))) > 0 && text.size() < 65536) {
        text.append(chunk, static_cast<std::size_t>(n));
    }
    ::close(fd);
    return text;
}

}  // namespace

std::string_view role_name(Role role) {
    return role == Role::kControl ? "control" : "view";
}

std::vector<Token> parse_tokens(std::string_view text) {
    std::vector<Token> tokens;
    int number = 0;
    while (!text.empty()) {
        const auto end = text.find('\n');
        const auto line = trim(text.substr(0, end));
        text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
        ++number;
        if (!line.empty() && line.front() != '#') {
            tokens.push_back(token_of(line, number));
            refuse_repeated(tokens, number);
        }
    }
    if (tokens.empty()) {
        throw std::runtime_error("no token in it");
    }
    return tokens;
}

TokenFile load_tokens(const std::string& path) {
    try {
        TokenFile file;
        if (!std::filesystem::exists(path)) {
            const auto secret = random_hex(32);
            if (create(path, secret)) {
                file.created = secret;
            }
        }
        file.tokens = parse_tokens(read_checked(path));
        return file;
    } catch (const std::exception& e) {
        throw std::runtime_error("token file " + path + ": " + e.what());
    }
}

std::optional<Role> role_of(const std::vector<Token>& tokens, std::string_view secret) {
    std::optional<Role> found;
    for (const auto& token : tokens) {
        unsigned char diff = token.secret.size() == secret.size() ? 0 : 1;
        for (std::size_t i = 0; i < token.secret.size(); ++i) {
            const char other = secret.empty() ? '\0' : secret[i % secret.size()];
            diff |= static_cast<unsigned char>(token.secret[i] ^ other);
        }
        if (diff == 0 && !found) {
            found = token.role;
        }
    }
    return found;
}

std::string random_hex(std::size_t bytes) {
    std::string raw(bytes, '\0');
    std::size_t got = 0;
    while (got < bytes) {
        const auto n = ::getrandom(raw.data() + got, bytes - got, 0);
        if (n < 0 && errno != EINTR) {
            throw std::runtime_error("getrandom: " + errno_text());
        }
        got += n > 0 ? static_cast<std::size_t>(n) : 0;
    }
    static constexpr char kHex[] = "0123456789abcdef";
    std::string hex;
    for (unsigned char c : raw) {
        hex += kHex[c >> 4];
        hex += kHex[c & 15];
    }
    return hex;
}

}  // namespace gport::web

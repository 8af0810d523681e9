#include "served_addresses.hpp"

#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>

#include <algorithm>
#include <cstring>
#include <optional>

namespace gport::web {
namespace {

namespace ip = boost::asio::ip;

std::optional<ip::address> address_of(const sockaddr* sa) {
    if (sa == nullptr) {
        return std::nullopt;
    }
    if (sa->sa_family == AF_INET) {
        sockaddr_in in{};
        std::memcpy(&in, sa, sizeof in);
        ip::address_v4::bytes_type bytes{};
        std::memcpy(bytes.data(), &in.sin_addr, bytes.size());
        return ip::address(ip::address_v4(bytes));
    }
    if (sa->sa_family == AF_INET6) {
        sockaddr_in6 in6{};
        std::memcpy(&in6, sa, sizeof in6);
        ip::address_v6::bytes_type bytes{};
        std::memcpy(bytes.data(), &in6.sin6_addr, bytes.size());
        return ip::address(ip::address_v6(bytes, in6.sin6_scope_id));
    }
    return std::nullopt;
}

ip::address plain(const ip::address& address) {
    if (address.is_v6() && address.to_v6().is_v4_mapped()) {
        return ip::make_address_v4(ip::v4_mapped, address.to_v6());
    }
    return address;
}

}  // namespace

std::vector<ip::address> served_addresses(const ip::address& listen) {
    if (!listen.is_unspecified()) {
        return {plain(listen)};
    }
    std::vector<ip::address> found;
    ifaddrs* list = nullptr;
    if (::getifaddrs(&list) != 0) {
        return {listen.is_v6() ? ip::address(ip::address_v6::loopback())
                               : ip::address(ip::address_v4::loopback())};
    }
    for (const ifaddrs* i = list; i != nullptr; i = i->ifa_next) {
        const auto address = (i->ifa_flags & IFF_UP) != 0 ? address_of(i->ifa_addr) : std::nullopt;
        if (address && (listen.is_v6() || address->is_v4()) &&
            std::find(found.begin(), found.end(), *address) == found.end()) {
            found.push_back(*address);
        }
    }
    ::freeifaddrs(list);
    std::stable_partition(found.begin(), found.end(),
                          [](const ip::address& a) { return !a.is_loopback(); });
    return found;
}

const std::vector<ip::address>& ServedAddresses::current() {
    const auto now = std::chrono::steady_clock::now();
    if (!read_ || now - read_at_ >= std::chrono::seconds(1)) {
        addresses_ = served_addresses(listen_);
        read_at_ = now;
        read_ = true;
    }
    return addresses_;
}

bool ServedAddresses::contains(const ip::address& address) {
    const auto& all = current();
    const auto wanted = plain(address);
    return std::any_of(all.begin(), all.end(), [&](const ip::address& a) {
        // An IPv6 Host names no zone: compare the address alone.
        if (a.is_v6() && wanted.is_v6()) {
            return a.to_v6().to_bytes() == wanted.to_v6().to_bytes();
        }
        return a == wanted;
    });
}

bool ServedAddresses::has_loopback() {
    const auto& all = current();
    return std::any_of(all.begin(), all.end(),
                       [](const ip::address& a) { return a.is_loopback(); });
}

}  // namespace gport::web

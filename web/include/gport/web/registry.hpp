// Every open connection of gport-web in one place, in the shape of Beast's
// chat-multi example's shared state: a connection joins when it is accepted,
// holding a Membership for as long as it lives, and leaves when its last
// operation ends. The registry
// - admits a new connection or turns it away (docs/web.md, "Limits"): at
//   most kMaxConnections, kMaxConnectionsPerAddress from one peer address,
//   and kMaxUnauthenticatedConnections that have not yet shown a valid
//   session or token, beyond which the oldest of those is closed to make
//   room, so that idle or slow peers cannot hold the slots the operator's
//   page needs;
// - fans one shared message out to the live sockets (weak pointers: a
//   connection on its way out is skipped);
// - closes every connection at exit, so that io.run() returns.
// One thread (gport-web's event loop) uses it: no lock.
#pragma once

#include <boost/asio/ip/address.hpp>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "gport/web/outbox.hpp"

namespace gport::web {

// The key a peer is counted under: an IPv4 address, or an IPv6 address's
// /64 (one host may hold a whole /64); a v4-mapped address as IPv4.
std::string peer_key(const boost::asio::ip::address& address);

// What a connection shows the registry: the HTTP session, then the live
// socket it may become.
class Member {
  public:
    virtual ~Member() = default;
    // Ends the connection's operations; their handlers then release it.
    virtual void close() = 0;
    // A message of the broadcast; only a member that listens gets one.
    virtual void deliver(const Message& message, bool attitude) = 0;
};

enum class Admission { kServe, kTooManyFromPeer, kFull };

class Registry {
  public:
    class Membership;

    Registry() = default;
    Registry(const Registry&) = delete;
    Registry& operator=(const Registry&) = delete;

    // Whether a new connection from `peer` (peer_key) is served; closes the
    // oldest unauthenticated connection when they are at their cap.
    Admission admit(const std::string& peer);
    // The connection joins: counted from now until the membership goes.
    std::unique_ptr<Membership> join(std::string peer);

    // To every member that listens.
    void broadcast(const Message& message, bool attitude);
    // Closes every member (at exit).
    void close_all();

    std::size_t size() const { return members_.size(); }
    std::size_t listening() const { return listening_; }
    std::size_t unauthenticated() const { return unauthenticated_; }
    std::size_t from(const std::string& peer) const;

  private:
    // kNew: no valid session or token shown yet (its room may be taken);
    // kTrusted: shown one; kClosing: evicted, counted until it has gone.
    enum class Standing { kNew, kTrusted, kClosing };
    struct Entry {
        std::string peer;
        std::weak_ptr<Member> member;
        Standing standing = Standing::kNew;
        bool listens = false;
    };

    void leave(std::uint64_t id);
    void authenticate(std::uint64_t id);
    void listen(std::uint64_t id, bool on);
    void evict_oldest_new();

    std::map<std::uint64_t, Entry> members_;  // by id: the oldest first
    std::map<std::string, std::size_t> per_address_;
    std::size_t unauthenticated_ = 0;
    std::size_t listening_ = 0;
    std::uint64_t next_ = 0;
};

// A connection's place in the registry; leaves it when destroyed. Moves
// with the connection from its HTTP session to its live socket.
class Registry::Membership {
  public:
    ~Membership() { registry_.leave(id_); }
    Membership(const Membership&) = delete;
    Membership& operator=(const Membership&) = delete;

    const std::string& peer() const { return peer_; }
    bool authenticated() const { return authenticated_; }
    // Who holds the connection now: the one closed when it must go.
    void hold(const std::weak_ptr<Member>& member) { registry_.members_.at(id_).member = member; }
    // It showed a valid session or token: its room is never taken.
    void authenticate() {
        authenticated_ = true;
        registry_.authenticate(id_);
    }
    // It receives the broadcasts (a live socket), or no longer.
    void listen(bool on) { registry_.listen(id_, on); }

  private:
    friend class Registry;
    Membership(Registry& registry, std::uint64_t id, std::string peer)
        : registry_(registry), id_(id), peer_(std::move(peer)) {}

    Registry& registry_;
    std::uint64_t id_;
    std::string peer_;
    bool authenticated_ = false;
};

}  // namespace gport::web

// The comparison's one reader: watchers of gportd (attitude subscribers on
// its Unix socket) and of gpsd (TCP clients that sent ?WATCH), all served by
// one epoll loop that stamps every line the same way, whichever daemon sent it.
#pragma once

#include <string>
#include <vector>

#include "clients.hpp"
#include "posix.hpp"

namespace gport::bench {

class WatchHub {
  public:
    WatchHub();

    // Connects `count` attitude subscribers to gportd's socket.
    void add_gportd(const std::string& socket, int count, int timeout_ms);
    // Connects `count` clients to gpsd on 127.0.0.1:`port`, each sending
    // ?WATCH={"enable":true,"json":true}.
    void add_gpsd(int port, int count, int timeout_ms);
    // Serves both until every watcher got its reply (the subscribe result,
    // gpsd's WATCH object); throws std::runtime_error after timeout_ms.
    void wait_ready(int timeout_ms);
    // Serves every watcher for `duration_ms`, stamping each line.
    void run_for(int duration_ms);

    const std::vector<Subscriber>& gportd() const { return gportd_; }
    const std::vector<Subscriber>& gpsd() const { return gpsd_; }

  private:
    void watch(int fd, std::uint64_t key);
    void poll_once(int timeout_ms);
    void on_readable(Subscriber& s, bool is_gpsd);
    bool all_ready() const;

    Fd epoll_;
    std::vector<Subscriber> gportd_;
    std::vector<Subscriber> gpsd_;
};

}  // namespace gport::bench

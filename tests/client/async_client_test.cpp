// The asynchronous client on a test-owned io_context, against gportd
// --simulate: calls, errors, a subscription, a timer sharing the loop, and
// the end of the connection.
#include "gport/client/async_client.hpp"

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <csignal>

#include "client_fixture.hpp"

namespace gport::testing {
namespace {

namespace asio = boost::asio;

class AsyncClientTest : public SimulatedDaemonTest {
  protected:
    // Runs the loop until `done` or 10 s.
    bool run_until(const bool& done) {
        asio::steady_timer guard(io_, 10s);
        guard.async_wait([&](boost::system::error_code ec) {
            if (!ec) {
                io_.stop();
            }
        });
        while (!done && !io_.stopped()) {
            io_.run_one();
        }
        guard.cancel();
        io_.restart();
        io_.poll();
        io_.restart();
        return done;
    }

    void connect(gc::AsyncClient& client) {
        bool done = false;
        client.async_connect(socket(), [&](std::optional<gc::Error> error) {
            EXPECT_FALSE(error) << error->what();
            done = true;
        });
        ASSERT_TRUE(run_until(done));
    }

    asio::io_context io_;
};

TEST_F(AsyncClientTest, CallsCompleteWithTypedResults) {
    gc::AsyncClient client(io_);
    connect(client);
    ASSERT_TRUE(client.connected());
    bool done = false;
    client.async_status([&](std::optional<gc::Error> error, gc::Status s) {
        EXPECT_FALSE(error);
        EXPECT_EQ(s.link.state, "up");
        client.async_speed({.yaw = 15}, {.duration = 2000ms},
                           [&](std::optional<gc::Error> e, gc::SpeedResult r) {
                               EXPECT_FALSE(e);
                               EXPECT_EQ(r.speed.yaw, 15);
                               client.async_stop([&](std::optional<gc::Error> e2, gc::Done) {
                                   EXPECT_FALSE(e2);
                                   done = true;
                               });
                           });
    });
    ASSERT_TRUE(run_until(done));

    // Several calls in flight at once; settings replies come when the gimbal
    // answers, possibly after later calls' replies.
    int completed = 0;
    bool all = false;
    const auto count = [&] { all = ++completed == 11; };
    client.async_attitude([&](auto error, gc::AttitudeSample a) {
        EXPECT_FALSE(error);
        EXPECT_GT(a.seq, 0U);
        count();
    });
    client.async_angle({.yaw = 5}, {}, [&](auto error, gc::AngleResult r) {
        EXPECT_FALSE(error);
        EXPECT_TRUE(r.sent);
        count();
    });
    client.async_center({}, [&](auto error, gc::CenterResult r) {
        EXPECT_FALSE(error);
        EXPECT_TRUE(r.sent);
        count();
    });
    client.async_lock([&](auto error, gc::Done) {
        EXPECT_FALSE(error);
        count();
    });
    client.async_photo([&](auto error, gc::Done) {
        EXPECT_FALSE(error);
        count();
    });
    client.async_record(true, true, [&](auto error, gc::RecordResult r) {
        EXPECT_FALSE(error);
        EXPECT_EQ(r.recording, "on");
        count();
    });
    client.async_acquire([&](auto error, gc::Control c) {
        EXPECT_FALSE(error);
        EXPECT_TRUE(c.you_hold_control);
        count();
    });
    client.async_release([&](auto error, gc::Control c) {
        EXPECT_FALSE(error);
        EXPECT_FALSE(c.you_hold_control);
        count();
    });
    client.async_settings([&](auto error, gc::Settings) {
        EXPECT_FALSE(error);
        count();
    });
    client.async_set_settings({.follow_speed = 7}, [&](auto error, gc::Settings s) {
        EXPECT_FALSE(error);
        EXPECT_EQ(s.follow_speed, 7);
        count();
    });
    client.async_unsubscribe({}, [&](auto error, gc::Subscription) {
        EXPECT_FALSE(error);
        count();
    });
    ASSERT_TRUE(run_until(all)) << completed << " of 11 completed";
}

TEST_F(AsyncClientTest, ErrorsCarryTheApiCode) {
    gc::AsyncClient client(io_);
    bool done = false;
    client.async_status([&](std::optional<gc::Error> error, gc::Status) {
        ASSERT_TRUE(error);
        EXPECT_TRUE(error->transport()) << "not connected yet";
        done = true;
    });
    ASSERT_TRUE(run_until(done));
    connect(client);
    done = false;
    client.async_angle({.pitch = 400}, {}, [&](std::optional<gc::Error> error, gc::AngleResult) {
        ASSERT_TRUE(error);
        EXPECT_EQ(error->code(), -32602);
        done = true;
    });
    ASSERT_TRUE(run_until(done));

    gc::AsyncClient absent(io_);
    done = false;
    absent.async_connect(dir_.file("absent.sock"), [&](std::optional<gc::Error> error) {
        ASSERT_TRUE(error);
        EXPECT_TRUE(error->transport());
        done = true;
    });
    ASSERT_TRUE(run_until(done));
}

TEST_F(AsyncClientTest, SubscriptionDeliversSamplesBesideATimer) {
    gc::AsyncClient client(io_);
    connect(client);
    int samples = 0;
    int motions = 0;
    client.on_notification([&](const gc::Notification& n) {
        samples += std::holds_alternative<gc::AttitudeSample>(n) ? 1 : 0;
        motions += std::holds_alternative<gc::MotionEvent>(n) ? 1 : 0;
    });
    bool subscribed = false;
    client.async_subscribe({"attitude", "motion"}, 20,
                           [&](std::optional<gc::Error> error, gc::Subscription s) {
                               EXPECT_FALSE(error);
                               EXPECT_EQ(s.topics.size(), 2U);
                               subscribed = true;
                           });
    ASSERT_TRUE(run_until(subscribed));
    bool ticked = false;  // a user timer on the same loop keeps working
    asio::steady_timer timer(io_, 300ms);
    timer.async_wait([&](boost::system::error_code ec) { ticked = !ec; });
    ASSERT_TRUE(run_until(ticked));
    client.async_speed({.roll = 3}, {.duration = 1000ms}, [](auto, gc::SpeedResult) {});
    bool enough = false;
    asio::steady_timer poll(io_);
    std::function<void()> check = [&] {
        if (samples >= 3 && motions >= 1) {
            enough = true;
            return;
        }
        poll.expires_after(50ms);
        poll.async_wait([&](boost::system::error_code) { check(); });
    };
    check();
    EXPECT_TRUE(run_until(enough)) << samples << " samples, " << motions << " motion events";
}

TEST_F(AsyncClientTest, DaemonGoingAwayFailsPendingCallsAndReportsTheDisconnect) {
    gc::AsyncClient client(io_);
    connect(client);
    std::optional<gc::Error> lost;
    client.on_disconnect([&](const gc::Error& e) { lost = e; });
    daemon_->process().signal(SIGTERM);
    ASSERT_TRUE(daemon_->process().wait().has_value());
    bool done = false;
    asio::steady_timer poll(io_);
    std::function<void()> check = [&] {
        if (lost) {
            done = true;
            return;
        }
        poll.expires_after(50ms);
        poll.async_wait([&](boost::system::error_code) { check(); });
    };
    check();
    ASSERT_TRUE(run_until(done));
    EXPECT_TRUE(lost->transport());
    EXPECT_FALSE(client.connected());

    daemon_ = std::make_unique<DaemonProcess>(dir_, std::vector<std::string>{"--simulate"});
    ASSERT_TRUE(eventually([&] {
        bool finished = false;
        bool ok = false;
        client.async_connect(socket(), [&](std::optional<gc::Error> error) {
            ok = !error;
            finished = true;
        });
        run_until(finished);
        return ok;
    }));
    bool answered = false;
    client.async_status([&](std::optional<gc::Error> error, gc::Status) {
        EXPECT_FALSE(error);
        answered = true;
    });
    EXPECT_TRUE(run_until(answered));
}

}  // namespace
}  // namespace gport::testing

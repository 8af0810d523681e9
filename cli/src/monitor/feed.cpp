#include "feed.hpp"

#include <fmt/format.h>

#include <ctime>
#include <thread>

#include "gport/contract/names.hpp"

namespace gport::cli::monitor {

using std::chrono::steady_clock;

Now current_time() {
    const std::time_t wall = std::time(nullptr);
    std::tm local{};
    ::localtime_r(&wall, &local);
    char clock[16];
    std::strftime(clock, sizeof clock, "%H:%M:%S", &local);
    return Now{steady_clock::now(), clock};
}

Feed::Feed(std::string socket, bool control)
    : socket_(std::move(socket)), control_(control), state_(socket_, control) {}

void Feed::open() {
    connect();
}

void Feed::connect() {
    auto client = client::Client::connect(socket_);
    client.on_notification(
        [this](const client::Notification& n) { state_.on_notification(n, current_time()); });
    if (control_) {
        const auto control = client.acquire();
        state_.on_control(control.you_hold_control, current_time());
    }
    client.subscribe({std::string(contract::kTopicAttitude), std::string(contract::kTopicLink),
                      std::string(contract::kTopicMotion)},
                     kAttitudeRateHz);
    client_.emplace(std::move(client));
    state_.on_connected(current_time());
    poll_status();
}

void Feed::poll_status() {
    next_status_ = steady_clock::now() + kStatusEvery;
    const auto status = client_->status();
    state_.on_status(status, current_time());
}

void Feed::lost(const client::Error& error) {
    client_.reset();
    state_.on_disconnected(error.message(), current_time());
    next_connect_ = steady_clock::now() + kReconnectEvery;
}

void Feed::pump(std::chrono::milliseconds wait) {
    if (!client_) {
        if (steady_clock::now() >= next_connect_) {
            try {
                connect();
            } catch (const client::Error& error) {
                lost(error);
            }
        }
        if (!client_) {
            std::this_thread::sleep_for(wait);
        }
        return;
    }
    try {
        client_->dispatch(wait);
        if (steady_clock::now() >= next_status_) {
            poll_status();
        }
    } catch (const client::Error& error) {
        if (error.transport()) {
            lost(error);
        } else {
            state_.note(fmt::format("status refused: {}", error.message()), Severity::kWarn,
                        current_time());
        }
    }
}

template <typename Call>
void Feed::command(const char* what, Call&& call) {
    if (!client_) {
        state_.note(fmt::format("{}: not connected to gportd", what), Severity::kWarn,
                    current_time());
        return;
    }
    try {
        call(*client_);
    } catch (const client::Error& error) {
        if (error.transport()) {
            lost(error);
            return;
        }
        state_.note(fmt::format("{} refused: {}", what, error.message()), Severity::kWarn,
                    current_time());
    }
}

void Feed::center() {
    command("centre", [this](client::Client& c) {
        c.center();
        state_.note("centre sent", Severity::kInfo, current_time());
    });
}

void Feed::nudge(const client::Axes& speed) {
    command("nudge", [&](client::Client& c) {
        c.speed(speed, client::SpeedOptions{.duration = kNudgeDuration, .lease = kNudgeDuration});
    });
}

void Feed::close() {
    if (client_ && control_) {
        try {
            client_->release();
        } catch (const client::Error&) {
            // Closing releases control anyway (the daemon's deadman).
        }
    }
    client_.reset();
}

}  // namespace gport::cli::monitor

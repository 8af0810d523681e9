// A hand-written daemon::Api for the IPC tests and the request fuzzer: it
// records every call, answers with what the test set up, and lets the test
// publish events through the registered observer.
#pragma once

#include <fmt/format.h>

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gport/daemon/api.hpp"

namespace gport::testing {

class FakeApi final : public daemon::Api {
  public:
    daemon::CoreObserver* observer = nullptr;
    daemon::Status status_value;
    std::optional<daemon::AttitudeSample> attitude;
    std::optional<daemon::CommandError> error;  // every command fails with it while set
    std::optional<daemon::ClientInfo> holder;
    daemon::Settings settings{10, 20, false};
    std::vector<std::string> clamped;  // what angle() and speed() report as clamped
    std::vector<std::string> braked;   // what speed() reports as braked
    bool emit_motion = false;          // speed() publishes a motion "started" event
    std::vector<std::string> calls;
    std::vector<daemon::ClientInfo> gone;
    std::vector<daemon::ClientInfo> closed;
    // Settings answers wait here until the test (or run_settings) runs them.
    std::vector<std::function<void()>> pending_settings;
    // The end callbacks of angle and center calls with `wait`, oldest first.
    std::vector<daemon::MotionEndCallback> waiters;
    // When set, settings answers are handed to it instead (e.g. asio::post).
    std::function<void(std::function<void()>)> defer;

    // Calls into the fake while one of its events is being published: the
    // server must never re-enter the core from inside its own emit.
    int emitting = 0;
    int reentered = 0;
    mutable std::size_t status_calls = 0;
    std::function<void()> on_status;  // runs on every status()

    void set_observer(daemon::CoreObserver* o) override { observer = o; }
    config::LimitsConfig limits_value;
    config::LimitsConfig limits() const override { return limits_value; }
    daemon::Millis max_duration_value{60000};
    daemon::Millis max_duration() const override { return max_duration_value; }

    daemon::Status status() const override {
        ++status_calls;
        if (on_status) {
            on_status();
        }
        auto s = status_value;
        if (holder) {
            s.controller = holder;
        }
        return s;
    }

    // Publishes like the core: from inside a call the observer must not re-enter.
    void emit_link(const daemon::LinkEvent& event) {
        ++emitting;
        observer->on_link(event);
        --emitting;
    }
    std::optional<daemon::AttitudeSample> latest_attitude() const override { return attitude; }
    bool may_command(const daemon::ClientInfo&) const override { return !error; }

    daemon::Outcome<daemon::SpeedStarted> speed(
        const daemon::ClientInfo& c, protocol::Axes s, std::optional<daemon::Millis> d,
        bool clamp = false, std::optional<daemon::Millis> lease = std::nullopt) override {
        calls.push_back(fmt::format("speed {} {} {} {}{}{} by {}", s.roll, s.pitch, s.yaw,
                                    d ? d->count() : -1, clamp ? " clamp" : "",
                                    lease ? fmt::format(" lease {}", lease->count()) : "", c.id));
        if (error) {
            return *error;
        }
        const auto duration = d.value_or(daemon::Millis(1000));
        if (emit_motion && observer != nullptr) {
            daemon::MotionEvent event;
            event.owner = c;
            event.speed = s;
            event.duration = duration;
            observer->on_motion(event);
        }
        return daemon::SpeedStarted{duration, std::chrono::system_clock::now() + duration, s,
                                    clamped, braked};
    }
    daemon::Outcome<daemon::Done> stop(const daemon::ClientInfo& c) override {
        return command("stop", c);
    }
    daemon::Outcome<daemon::AngleSent> angle(const daemon::ClientInfo& c, protocol::Axes a,
                                             bool clamp = false,
                                             daemon::MotionEndCallback on_end = {}) override {
        auto done = command(fmt::format("angle {} {} {}{}{}", a.roll, a.pitch, a.yaw,
                                        clamp ? " clamp" : "", on_end ? " wait" : ""),
                            c);
        if (!done) {
            return done.error();
        }
        if (on_end) {
            waiters.push_back(std::move(on_end));
        }
        return daemon::AngleSent{a, clamped};
    }
    daemon::Outcome<daemon::AngleSent> center(const daemon::ClientInfo& c,
                                              daemon::MotionEndCallback on_end = {}) override {
        auto done = command(on_end ? "center wait" : "center", c);
        if (!done) {
            return done.error();
        }
        if (on_end) {
            waiters.push_back(std::move(on_end));
        }
        return daemon::AngleSent{};
    }
    // Ends the oldest waiting motion with `end` (as the core would, later).
    void end_waiter(const daemon::MotionEnd& end) {
        auto on_end = std::move(waiters.front());
        waiters.erase(waiters.begin());
        on_end(end);
    }
    daemon::Outcome<daemon::Done> lock(const daemon::ClientInfo& c) override {
        return command("lock", c);
    }
    // What photo and record stamp their captures with.
    std::optional<daemon::VehicleStamp> vehicle_stamp;
    daemon::CaptureMoment moment() const {
        const auto now = std::chrono::steady_clock::now();
        return daemon::CaptureMoment{now, now, vehicle_stamp};
    }
    daemon::Outcome<daemon::CaptureMoment> photo(const daemon::ClientInfo& c) override {
        if (auto done = command("photo", c); !done) {
            return done.error();
        }
        return moment();
    }
    std::vector<daemon::VehicleReport> vehicle_reports;
    daemon::Outcome<daemon::Done> publish_vehicle(const daemon::ClientInfo& c,
                                                  const daemon::VehicleReport& report) override {
        vehicle_reports.push_back(report);
        return command("publish_vehicle", c);
    }
    // record answers with this (sent, recording) unless `error` is set.
    daemon::RecordResult record_result{true, daemon::RecordingState::kUnknown};
    daemon::Outcome<daemon::RecordResult> record(const daemon::ClientInfo& c,
                                                 daemon::RecordRequest r) override {
        auto done = command(fmt::format("record {} {}", r.on ? (*r.on ? "on" : "off") : "toggle",
                                        r.force ? "force" : "-"),
                            c);
        if (!done) {
            return done.error();
        }
        auto result = record_result;
        if (result.sent) {
            result.moment = moment();
        }
        return result;
    }
    daemon::Outcome<std::optional<daemon::ClientInfo>> acquire(
        const daemon::ClientInfo& c) override {
        calls.push_back(fmt::format("acquire by {}", c.id));
        if (error) {
            return *error;
        }
        holder = c;
        return holder;
    }
    daemon::Outcome<std::optional<daemon::ClientInfo>> release(
        const daemon::ClientInfo& c) override {
        calls.push_back(fmt::format("release by {}", c.id));
        if (error) {
            return *error;
        }
        holder.reset();
        return holder;
    }
    void get_settings(const daemon::ClientInfo& c, SettingsCallback done) override {
        calls.push_back(fmt::format("get_settings by {}", c.id));
        answer(std::move(done));
    }
    void set_settings(const daemon::ClientInfo& c, daemon::SettingsChange change,
                      SettingsCallback done) override {
        calls.push_back(fmt::format("set_settings {} {} {} by {}",
                                    change.dead_zone ? int{*change.dead_zone} : -1,
                                    change.follow_speed ? int{*change.follow_speed} : -1,
                                    change.inverted ? int{*change.inverted} : -1, c.id));
        if (!error) {
            settings.dead_zone = change.dead_zone.value_or(settings.dead_zone);
            settings.follow_speed = change.follow_speed.value_or(settings.follow_speed);
            settings.inverted = change.inverted.value_or(settings.inverted);
        }
        answer(std::move(done));
    }
    void client_gone(const daemon::ClientInfo& c) override {
        reentered += emitting;
        gone.push_back(c);
    }
    void client_closed(const daemon::ClientInfo& c) override {
        reentered += emitting;
        closed.push_back(c);
    }

    void run_settings() {
        auto pending = std::move(pending_settings);
        pending_settings.clear();
        for (auto& run : pending) {
            run();
        }
    }

  private:
    daemon::Outcome<daemon::Done> command(std::string name, const daemon::ClientInfo& c) {
        calls.push_back(fmt::format("{} by {}", name, c.id));
        if (error) {
            return *error;
        }
        return daemon::Done{};
    }

    void answer(SettingsCallback done) {
        auto run = [this, done = std::move(done)] {
            if (error) {
                done(*error);
            } else {
                done(settings);
            }
        };
        if (defer) {
            defer(std::move(run));
        } else {
            pending_settings.push_back(std::move(run));
        }
    }
};

}  // namespace gport::testing

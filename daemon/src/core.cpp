#include "gport/daemon/core.hpp"

#include <fmt/format.h>

#include <boost/asio/steady_timer.hpp>

#include "access_policy.hpp"
#include "core_impl.hpp"

namespace gport::daemon {

Core::Core(boost::asio::io_context& io, const config::Config& config,
           std::shared_ptr<spdlog::logger> log)
    : impl_(std::make_unique<Impl>(io, config, std::move(log))) {}

Core::~Core() = default;

void Core::start() {
    impl_->start();
}
void Core::shutdown(std::function<void()> done) {
    impl_->shutdown(std::move(done));
}
void Core::reload(const config::Config& config) {
    impl_->reload(config);
}

// Kept here, apart from core_impl.cpp: the only state a reload touches.
void Core::Impl::reload(const config::Config& config) {
    access = AccessPolicy(config.access);
    config_.keepalive.default_duration = config.keepalive.default_duration;
    config_.keepalive.max_duration = config.keepalive.max_duration;
}

void Core::add_link_listener(std::function<void(const LinkEvent&)> listener) {
    impl_->link_listeners.push_back(std::move(listener));
}
void Core::set_observer(CoreObserver* observer) {
    impl_->observer = observer;
}
Status Core::status() const {
    return impl_->status();
}
std::optional<AttitudeSample> Core::latest_attitude() const {
    return impl_->latest;
}
bool Core::may_command(const ClientInfo& client) const {
    return impl_->access.may_command(client);
}

Outcome<SpeedStarted> Core::speed(const ClientInfo& client, protocol::Axes speed,
                                  std::optional<Millis> duration) {
    return impl_->speed(client, speed, duration);
}

Outcome<Done> Core::stop(const ClientInfo& client) {
    return impl_->stop(client);
}

Outcome<Done> Core::angle(const ClientInfo& client, protocol::Axes angle) {
    return impl_->position(client, protocol::Control::angle_of(angle), MotionMode::kAngle);
}

Outcome<Done> Core::center(const ClientInfo& client) {
    return impl_->position(client, protocol::Control::center(), MotionMode::kCenter);
}

Outcome<Done> Core::lock(const ClientInfo& client) {
    return impl_->position(client, protocol::Control::lock(), MotionMode::kLock);
}

Outcome<Done> Core::photo(const ClientInfo& client) {
    return impl_->camera(client, protocol::CameraAction::kPhoto);
}

Outcome<Done> Core::record(const ClientInfo& client) {
    return impl_->camera(client, protocol::CameraAction::kToggleRecording);
}

Outcome<std::optional<ClientInfo>> Core::acquire(const ClientInfo& client) {
    return impl_->acquire(client);
}

Outcome<std::optional<ClientInfo>> Core::release(const ClientInfo& client) {
    return impl_->release(client);
}

void Core::get_settings(const ClientInfo& client, SettingsCallback done) {
    impl_->settings(client, std::nullopt, std::move(done));
}

void Core::set_settings(const ClientInfo& client, SettingsChange change, SettingsCallback done) {
    impl_->settings(client, change, std::move(done));
}

void Core::client_gone(const ClientInfo& client) {
    impl_->client_gone(client);
}

void Core::client_closed(const ClientInfo& client) {
    impl_->client_closed(client);
}

}  // namespace gport::daemon

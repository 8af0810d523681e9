#include "attitude_channel.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>
#include <utility>

#include "gport/ipc/json_rpc.hpp"
#include "json_common.hpp"

namespace gport::ipc::detail {
namespace {

constexpr unsigned kSeals = F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE | F_SEAL_SEAL;

std::string failed(const char* step) {
    return std::string(step) + ": " + std::strerror(errno);
}

}  // namespace

base::RingSample ring_sample(const daemon::AttitudeSample& sample) {
    const auto& a = sample.attitude;
    base::RingSample out;
    out.seq = sample.seq;
    out.t = epoch_seconds(sample.wall);
    out.imu = protocol::degrees_of(a.imu);
    out.hall = protocol::degrees_of(a.hall);
    if (a.rates) {
        out.has_rates = true;
        out.hall_rates = protocol::degrees_of(a.rates->hall);
        out.imu_rates = {protocol::from_centi(a.rates->imu_x), protocol::from_centi(a.rates->imu_y),
                         protocol::from_centi(a.rates->imu_z)};
    }
    return out;
}

AttitudeChannel::~AttitudeChannel() {
    if (memory_ != nullptr) {
        ::munmap(memory_, kBytes);
    }
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

std::optional<std::string> AttitudeChannel::open() {
    if (writer_) {
        return std::nullopt;
    }
    if (auto error = waker_.start()) {
        return error;
    }
    const int fd = ::memfd_create("gportd-attitude", MFD_CLOEXEC | MFD_ALLOW_SEALING);
    if (fd < 0) {
        return failed("memfd_create");
    }
    if (::ftruncate(fd, static_cast<off_t>(kBytes)) != 0) {
        auto error = failed("ftruncate");
        ::close(fd);
        return error;
    }
    void* memory = ::mmap(nullptr, kBytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (memory == MAP_FAILED) {
        auto error = failed("mmap");
        ::close(fd);
        return error;
    }
    base::RingWriter writer(memory, kSlots);  // formats the zero-filled block
    if (::fcntl(fd, F_ADD_SEALS, kSeals) != 0) {
        auto error = failed("sealing the memfd");
        ::munmap(memory, kBytes);
        ::close(fd);
        return error;
    }
    fd_ = fd;
    memory_ = memory;
    writer_.emplace(writer);
    return std::nullopt;
}

std::variant<std::size_t, std::string> AttitudeChannel::open_for(std::uint64_t client,
                                                                 bool deliver) {
    if (auto error = open()) {
        return *error;
    }
    auto it = readers_.find(client);
    if (it == readers_.end()) {
        auto made = WakeBlock::make();
        if (auto* error = std::get_if<std::string>(&made)) {
            return *error;
        }
        it = readers_
                 .emplace(client, Reader{std::shared_ptr<WakeBlock>(std::move(std::get<0>(made)))})
                 .first;
    }
    if (!deliver || it->second.delivery != Delivery::kUnsent) {
        return std::size_t{0};  // a reply nobody sends, or they are on their way or there
    }
    it->second.delivery = Delivery::kQueued;
    return kDescriptors;
}

std::array<int, 2> AttitudeChannel::descriptors(std::uint64_t client) const {
    const auto it = readers_.find(client);
    if (it == readers_.end() || fd_ < 0 || it->second.block->fd() < 0) {
        return {-1, -1};
    }
    return {fd_, it->second.block->fd()};
}

void AttitudeChannel::delivered(std::uint64_t client, int error) {
    const auto it = readers_.find(client);
    if (it == readers_.end()) {
        return;
    }
    if (error != 0) {
        it->second.delivery = Delivery::kUnsent;
        return;
    }
    it->second.delivery = Delivery::kSent;
    it->second.block->forget_descriptor();  // the mapping is all gportd needs
    ++woken_readers_;
    update_waker();
}

void AttitudeChannel::forget(std::uint64_t client) {
    const auto it = readers_.find(client);
    if (it == readers_.end()) {
        return;
    }
    const bool woken = it->second.delivery == Delivery::kSent;
    readers_.erase(it);
    if (woken) {
        --woken_readers_;
        update_waker();
    }
}

// O(readers), bounded by socket.max_clients; only when a connection's
// descriptors went out or a reader left, never per sample.
void AttitudeChannel::update_waker() {
    ChannelWaker::Blocks blocks;
    blocks.reserve(woken_readers_);
    for (const auto& [id, reader] : readers_) {
        if (reader.delivery == Delivery::kSent) {  // nobody can wait on the others yet
            blocks.push_back(reader.block);
        }
    }
    waker_.set_blocks(std::move(blocks));
}

void AttitudeChannel::publish(const daemon::AttitudeSample& sample) {
    if (writer_ && !closed_) {
        writer_->publish(ring_sample(sample));
    }
}

void AttitudeChannel::wake() {
    if (woken_readers_ > 0 && !closed_) {
        waker_.signal();
    }
}

void AttitudeChannel::close() {
    if (!writer_ || closed_) {
        waker_.close();
        return;
    }
    closed_ = true;
    writer_->close();  // before the last round: a reader it wakes sees the flag
    waker_.close();
}

std::string unsent_reply(const std::string& line, const std::string& why) {
    nlohmann::json reply = nlohmann::json::parse(line, nullptr, false);
    const nlohmann::json error = {{"code", rpc_error::kInternal},
                                  {"message", std::string(kUnavailable) + why}};
    const auto replace = [&error](nlohmann::json& member) {
        if (member.is_object() && member.contains("result") && member["result"].is_object() &&
            member["result"].contains("slots") && member["result"].value("descriptors", 0) > 0) {
            member.erase("result");
            member["error"] = error;
        }
    };
    if (reply.is_array()) {
        for (auto& member : reply) {
            replace(member);
        }
    } else {
        replace(reply);
    }
    return reply.dump() + '\n';
}

}  // namespace gport::ipc::detail

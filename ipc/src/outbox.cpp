#include "gport/ipc/outbox.hpp"

#include <algorithm>
#include <utility>

namespace gport::ipc {

Outbox::Outbox(std::size_t line_limit, std::size_t byte_limit)
    : line_limit_(std::max<std::size_t>(line_limit, 1)), byte_limit_(byte_limit) {}

bool Outbox::fits(std::size_t size) const {
    return queue_.size() < line_limit_ && bytes_ + size <= byte_limit_;
}

bool Outbox::drop_oldest_attitude() {
    auto it = std::find_if(queue_.begin(), queue_.end(), [](const Entry& e) { return e.attitude; });
    if (it == queue_.end()) {
        return false;
    }
    bytes_ -= it->line->size();
    attitude_bytes_ -= it->line->size();
    queue_.erase(it);
    ++dropped_;
    report_drops_ = true;
    return true;
}

void Outbox::append(Line line, bool attitude, std::size_t descriptors) {
    bytes_ += line->size();
    attitude_bytes_ += attitude ? line->size() : 0;
    queue_.push_back({std::move(line), attitude, descriptors});
}

bool Outbox::push(Line line, std::size_t descriptors) {
    while (!fits(line->size())) {
        if (!drop_oldest_attitude()) {
            return false;
        }
    }
    append(std::move(line), false, descriptors);
    return true;
}

std::size_t Outbox::push_attitude(const AttitudeLine& line) {
    // Room for the line and a ,"dropped":<count> field it may have to carry.
    constexpr std::size_t kDropField = 32;
    const auto before = dropped_;
    while (!fits(line->text.size() + kDropField)) {
        if (!drop_oldest_attitude()) {
            ++dropped_;  // nothing older to give up: this one goes
            report_drops_ = true;
            return static_cast<std::size_t>(dropped_ - before);
        }
    }
    append(report_drops_ ? with_dropped(*line, dropped_) : text_of(line), true);
    report_drops_ = false;
    return static_cast<std::size_t>(dropped_ - before);
}

std::size_t Outbox::drop_attitude() {
    ++dropped_;
    report_drops_ = true;
    return 1;
}

void Outbox::take(std::vector<Line>& out, std::size_t max_lines) {
    while (!queue_.empty() && queue_.front().descriptors == 0 && max_lines-- > 0) {
        out.push_back(pop_front());
    }
}

std::size_t Outbox::front_descriptors() const {
    return queue_.empty() ? 0 : queue_.front().descriptors;
}

Line Outbox::pop_front() {
    const auto size = queue_.front().line->size();
    bytes_ -= size;
    attitude_bytes_ -= queue_.front().attitude ? size : 0;
    Line line = std::move(queue_.front().line);
    queue_.pop_front();
    return line;
}

void Outbox::replace_front(Line line) {
    Entry& front = queue_.front();
    bytes_ = bytes_ - front.line->size() + line->size();
    front = Entry{std::move(line), false, 0};
}

}  // namespace gport::ipc

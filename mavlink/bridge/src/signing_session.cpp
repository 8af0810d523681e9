#include "signing_session.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>

#include "gport/mavlink/messages.hpp"

namespace gport::mavlink::bridge {

namespace {

std::uint64_t now_timestamp() {
    return signing_timestamp(std::chrono::system_clock::now());
}

double seconds(std::uint64_t timestamps) {
    return static_cast<double>(timestamps) / kTimestampsPerSecond;
}

std::string describe(const FrameView& frame) {
    return fmt::format("{} from system {} component {}", message_name(frame.msgid),
                       frame.header.sysid, frame.header.compid);
}

// The limiter's kinds: fixed texts, not made per frame.
std::string_view drop_kind(SignatureCheck check) {
    switch (check) {
        case SignatureCheck::kUnsigned:
            return "signing: unsigned frames dropped";
        case SignatureCheck::kBadSignature:
            return "signing: bad signature frames dropped";
        case SignatureCheck::kReplayed:
            return "signing: replayed frames dropped";
        case SignatureCheck::kTooOld:
            return "signing: too old frames dropped";
        case SignatureCheck::kStreamsFull:
            return "signing: stream table full frames dropped";
        case SignatureCheck::kAccepted:
            break;
    }
    return "signing: frames dropped";
}

}  // namespace

Result<std::unique_ptr<SigningSession>> SigningSession::open(SecretKey key,
                                                             const std::string& state_dir,
                                                             Logbook& log) {
    TimestampFile file(state_dir);
    if (auto error = file.lock()) {
        return *error;
    }
    const auto stored = file.load();
    if (!stored) {
        return stored.error();
    }
    const std::uint64_t now = now_timestamp();
    std::unique_ptr<SigningSession> session(
        new SigningSession(std::move(key), std::move(file), trusted_floor(*stored, now), now, log));
    // The exact start value: checks that the file can be written, without
    // reserving anything before a frame is sent.
    const std::uint64_t start = session->clock_.current();
    if (auto error = session->file_.save(start)) {
        session->closed_ = true;
        return *error;
    }
    session->reserved_ = start;
    session->explain_start(*stored, now);
    return session;
}

void SigningSession::explain_start(std::uint64_t stored, std::uint64_t now) const {
    const std::uint64_t start = clock_.current();
    if (stored > start + kReservation) {
        // More than a crash's reservation above what we take: not ours.
        spdlog::error(
            "signing: the stored timestamp {} in {} is {:.0f} s ahead of this machine's clock: "
            "not trusted beyond {:.0f} s ahead (our frames never run further ahead, so it was "
            "planted, or set by a peer's clock through an older gport-mavlink); starting at "
            "{}. If this machine's clock went back instead, set it right (NTP, GPS): peers "
            "that saw our earlier frames refuse lower timestamps as replays until they restart",
            stored, file_.path(), seconds(stored - now), seconds(SendClock::kMaxLead), start);
    }
    spdlog::info(
        "signing: on (link id {}); only correctly signed frames are taken; outgoing timestamps "
        "above {} (stored {}, clock {}), kept in {}",
        kLinkId, start, stored, now, file_.path());
}

SigningSession::SigningSession(SecretKey key, TimestampFile file, std::uint64_t floor,
                               std::uint64_t now, Logbook& log)
    : key_(key), verifier_(std::move(key)), file_(std::move(file)), clock_(floor, now), log_(log) {}

std::optional<Error> SigningSession::reserve(std::uint64_t timestamp) {
    // After a failed write, one attempt a second, not one per frame: each
    // costs a file system call on the event loop.
    const auto now = std::chrono::steady_clock::now();
    if (now < retry_at_) {
        return std::nullopt;
    }
    const std::uint64_t value = std::min(timestamp + kReservation, kMaxTimestamp);
    if (auto error = file_.save(value)) {
        retry_at_ = now + std::chrono::seconds(1);
        return error;
    }
    reserved_ = value;  // only once it is on disk
    return std::nullopt;
}

bool SigningSession::admit(const FrameView& frame) {
    const Verdict verdict = verifier_.check(frame.bytes, clock_.reference(now_timestamp()));
    ++counts_[static_cast<std::size_t>(verdict.check)];
    if (verdict.check == SignatureCheck::kAccepted) {
        return true;
    }
    report(frame, verdict);
    return false;
}

void SigningSession::follow(const FrameView& frame) {
    const auto block = signature_block_of(frame.bytes);
    if (!block) {
        return;
    }
    const std::uint64_t now = now_timestamp();
    const auto observed = clock_.observe(block->timestamp, now);
    if (observed.capped) {
        log_.note(spdlog::level::err, "signing: a peer's timestamp is far ahead", [&] {
            return fmt::format(
                "signing: {} carries timestamp {}, {:.0f} s ahead of our clock: ours follows "
                "it to {:.0f} s ahead at most; is that sender's clock, or this machine's, wrong?",
                describe(frame), block->timestamp, seconds(block->timestamp - now),
                seconds(SendClock::kMaxLead));
        });
    } else if (observed.raised > kNotedStep) {
        log_.note(spdlog::level::warn, "signing: timestamp moved by a peer", [&] {
            return fmt::format(
                "signing: {} moved our timestamp {:.1f} s forward, to {:.1f} s ahead of our "
                "clock",
                describe(frame), seconds(observed.raised),
                seconds(clock_.current() > now ? clock_.current() - now : 0));
        });
    }
}

void SigningSession::report(const FrameView& frame, const Verdict& verdict) {
    log_.warn(drop_kind(verdict.check), [&] { return drop_text(frame, verdict); });
}

std::string SigningSession::drop_text(const FrameView& frame, const Verdict& verdict) const {
    std::string text;
    switch (verdict.check) {
        case SignatureCheck::kUnsigned:
            text = fmt::format(
                "signing: dropped an unsigned {}: with a signing key only "
                "correctly signed frames are taken",
                describe(frame));
            break;
        case SignatureCheck::kBadSignature:
            text = fmt::format(
                "signing: dropped {} with a wrong signature (not made with our "
                "key, or altered)",
                describe(frame));
            break;
        case SignatureCheck::kReplayed:
            text = fmt::format(
                "signing: dropped a replayed {}: timestamp {} is not newer "
                "than the last of its stream",
                describe(frame), verdict.timestamp);
            break;
        case SignatureCheck::kTooOld:
            text = fmt::format(
                "signing: dropped {}: a new stream whose timestamp {} is more "
                "than a minute behind ours ({}); is the sender's clock right?",
                describe(frame), verdict.timestamp, clock_.current());
            break;
        case SignatureCheck::kStreamsFull:
            text = fmt::format(
                "signing: dropped {}: its stream is new and the table of {} "
                "streams is full of recent ones",
                describe(frame), verifier_.max_streams());
            break;
        case SignatureCheck::kAccepted:
            break;
    }
    return text;
}

void SigningSession::sign(Frame& frame) {
    const std::uint64_t timestamp = clock_.next(now_timestamp());
    if (clock_.saturated()) {
        log_.note(spdlog::level::err, "signing: timestamp saturated", [&] {
            return fmt::format(
                "signing: the outgoing timestamp is saturated at 2^48 - 1: every frame repeats "
                "it and receivers take only the first. If this machine's clock is right, stop "
                "gport-mavlink, remove {} and start it again",
                file_.path());
        });
    }
    if (timestamp + kHeadroom > reserved_) {
        if (auto error = reserve(timestamp)) {
            log_.warn("signing: timestamp not saved",
                      "signing: " + error->message +
                          "; after a restart the bridge's frames may be refused as replays "
                          "until its clock passes the last timestamp sent");
        }
    }
    mavlink::sign(frame, key_, kLinkId, timestamp);
}

void SigningSession::close() {
    if (closed_) {
        return;
    }
    closed_ = true;
    if (auto error = file_.save(clock_.current())) {
        spdlog::warn("signing: {}", error->message);
    }
}

SigningSession::~SigningSession() {
    try {
        close();
    } catch (...) {  // NOLINT(bugprone-empty-catch): nothing to do at exit
    }
}

}  // namespace gport::mavlink::bridge

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
        new SigningSession(std::move(key), std::move(file), *stored, now, log));
    // The exact start value: checks that the file can be written, without
    // reserving anything before a frame is sent.
    const std::uint64_t start = session->clock_.current();
    if (auto error = session->file_.save(start)) {
        session->closed_ = true;
        return *error;
    }
    session->reserved_ = start;
    if (session->clock_.saturated()) {
        spdlog::error(
            "signing: the stored timestamp in {} is saturated at 2^48 - 1: every frame will "
            "repeat it and receivers take only the first. If this machine's clock is right, "
            "stop gport-mavlink, remove the file and start it again",
            session->file_.path());
    } else if (*stored > now + kAheadWarning) {
        spdlog::warn(
            "signing: the stored timestamp {} in {} is {:.0f} s ahead of this machine's clock: "
            "until the clock catches up, a peer whose clock is right starts its streams more "
            "than a minute behind ours and is refused as \"too old\". Is the clock right? (If "
            "it is, the value came from a peer's clock or an old bug; removing the file while "
            "gport-mavlink is stopped makes peers that saw our earlier frames refuse the next "
            "ones as replays until they restart.)",
            *stored, session->file_.path(),
            static_cast<double>(*stored - now) / kTimestampsPerSecond);
    }
    spdlog::info(
        "signing: on (link id {}); only correctly signed frames are taken; outgoing timestamps "
        "above {} (stored {}, clock {}), kept in {}",
        kLinkId, session->clock_.current(), *stored, now, session->file_.path());
    return session;
}

SigningSession::SigningSession(SecretKey key, TimestampFile file, std::uint64_t stored,
                               std::uint64_t now, Logbook& log)
    : key_(key),
      verifier_(std::move(key)),
      file_(std::move(file)),
      clock_(stored, now),
      log_(log) {}

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
    const std::uint64_t local = std::max(clock_.current(), now_timestamp());
    const Verdict verdict = verifier_.check(frame.bytes, local);
    ++counts_[static_cast<std::size_t>(verdict.check)];
    if (verdict.check == SignatureCheck::kAccepted) {
        if (!clock_.observe(verdict.timestamp, now_timestamp())) {
            log_.note(spdlog::level::err, "signing: a peer's timestamp is over a day ahead", [&] {
                return fmt::format(
                    "signing: {} carries timestamp {}, more than a day ahead of our clock: "
                    "ours is raised to a day ahead at most (not further, or it could saturate "
                    "at 2^48 - 1 and repeat one timestamp for good); is that sender's clock, "
                    "or this machine's, wrong?",
                    describe(frame), verdict.timestamp);
            });
        }
        return true;
    }
    report(frame, verdict);
    return false;
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

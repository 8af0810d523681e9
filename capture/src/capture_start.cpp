// gportd's start-up of the capture log: the directory checked, the files
// read back into the log, and the writer with its first reservation.
#include <utility>

#include "gport/capture/capture_writer.hpp"

namespace gport::capture {
namespace {

// The sink of a log whose directory was refused: nothing written, every
// line counted as dropped, the reason in status.
class RefusedSink final : public CaptureSink {
  public:
    explicit RefusedSink(std::string reason) { stats_.error = std::move(reason); }
    void write(std::string /*line*/) override { ++stats_.dropped; }
    Stats stats() const override { return stats_; }
    std::string path() const override { return ""; }

  private:
    Stats stats_;
};

}  // namespace

OpenedCaptureLog open_capture_log(const CaptureFiles& files, CaptureLog& captures,
                                  const std::shared_ptr<spdlog::logger>& log) {
    if (auto refused = check_capture_dir(files.dir)) {
        log->error(
            "capture log kept in memory only (its indexes restart at 1): {}; gportd writes its "
            "captures only into a directory no one else may write",
            *refused);
        return {
            std::make_unique<RefusedSink>(*refused + "; the capture log is kept in memory only")};
    }
    const auto restored = read_captures(files, CaptureLog::kKept);
    for (const auto& problem : restored.problems) {
        log->warn("capture log: {}", problem);
    }
    captures.restore(restored.lines, restored.next_index);
    auto writer = std::make_unique<CaptureWriter>(
        files, restored.next_index + CaptureWriter::kFirstReservation, log);
    if (const auto reserved = writer->reserved()) {
        log->info("capture log: {} (next index {}, reserved up to {})", files.file(0),
                  restored.next_index, *reserved);
    }
    auto* raw = writer.get();
    return {std::move(writer), raw};
}

}  // namespace gport::capture

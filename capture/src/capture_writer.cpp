#include "gport/capture/capture_writer.hpp"

#include <utility>

#include "capture_worker.hpp"

namespace gport::capture {

CaptureWriter::CaptureWriter(CaptureFiles files, std::uint64_t first_mark,
                             std::shared_ptr<spdlog::logger> log, std::size_t queue_limit,
                             std::chrono::milliseconds exit_wait)
    : path_(files.file(0)),
      exit_wait_(exit_wait),
      worker_(std::make_shared<CaptureWorker>(std::move(files), std::move(log), queue_limit)) {
    worker_->start_mark(first_mark);
    // The thread holds the worker too: left behind at exit, it outlives us.
    thread_ = std::thread([worker = worker_] { worker->run(); });
}

CaptureWriter::~CaptureWriter() {
    if (worker_->stop(exit_wait_)) {
        thread_.join();
    } else {
        thread_.detach();  // stuck in the kernel on a stalled disk; the process exits without it
    }
}

void CaptureWriter::write(std::string line) {
    worker_->push(std::move(line));
}

void CaptureWriter::reserve(std::uint64_t upto) {
    worker_->reserve(upto);
}

std::optional<std::uint64_t> CaptureWriter::reserved() const {
    return worker_->reserved();
}

CaptureSink::Stats CaptureWriter::stats() const {
    return worker_->stats();
}

void CaptureWriter::finish(std::uint64_t next_index) {
    worker_->finish(next_index);
}

void CaptureWriter::drain() {
    worker_->drain();
}

}  // namespace gport::capture

// gportctl monitor's two loops: the full-screen view on a terminal, the
// plain status block otherwise. Both read the feed in short slices so that
// keys, signals and the frame clock are looked at often.
#include "gport/cli/monitor.hpp"

#include <cstdlib>
#include <stdexcept>

#include "charset.hpp"
#include "feed.hpp"
#include "gport/cli/options.hpp"
#include "gport/cli/output.hpp"
#include "gport/cli/printable.hpp"
#include "keys.hpp"
#include "render.hpp"
#include "terminal.hpp"

namespace gport::cli {
namespace {

using namespace std::chrono_literals;
using monitor::Feed;
using std::chrono::steady_clock;

constexpr auto kFrameEvery = 100ms;   // ~10 frames a second
constexpr auto kSlice = 20ms;         // how long one read of the feed may wait
constexpr auto kBlockEvery = 1000ms;  // plain status blocks

bool use_color(ColorMode mode) {
    if (mode != ColorMode::kAuto) {
        return mode == ColorMode::kAlways;
    }
    const char* no_color = std::getenv("NO_COLOR");  // https://no-color.org
    return no_color == nullptr || *no_color == '\0';
}

monitor::Charset charset_of(const MonitorOptions& options) {
    return options.ascii ? monitor::Charset::kAscii : monitor::charset_from_locale();
}

steady_clock::time_point deadline_of(const MonitorOptions& options) {
    return options.duration ? steady_clock::now() + *options.duration
                            : steady_clock::time_point::max();
}

// Acts on one key; false for quit.
bool handle_key(monitor::Key key, Feed& feed, bool control) {
    const double v = monitor::kNudgeSpeedDegPerS;
    switch (key) {
        case monitor::Key::kQuit:
            return false;
        case monitor::Key::kCentre:
            feed.center();
            return true;
        case monitor::Key::kLeft:
        case monitor::Key::kRight:
        case monitor::Key::kUp:
        case monitor::Key::kDown:
            break;
    }
    if (!control) {
        return true;  // the key line says arrows need --control
    }
    client::Axes speed{};
    if (key == monitor::Key::kLeft || key == monitor::Key::kRight) {
        speed.yaw = key == monitor::Key::kRight ? v : -v;
    } else {
        speed.pitch = key == monitor::Key::kUp ? v : -v;
    }
    feed.nudge(speed);
    return true;
}

int full_screen(const MonitorOptions& options, Feed& feed,
                const std::function<bool()>& interrupted) {
    const bool color = use_color(options.color);
    const auto charset = charset_of(options);
    const auto deadline = deadline_of(options);
    monitor::Terminal terminal;
    std::optional<monitor::Screen> shown;
    std::string pending;
    auto next_frame = steady_clock::now();
    while (!interrupted() && steady_clock::now() < deadline) {
        feed.pump(kSlice);
        pending += terminal.read_input();
        for (auto key : monitor::take_keys(pending)) {
            if (!handle_key(key, feed, options.control)) {
                return kExitOk;
            }
            next_frame = steady_clock::now();  // show the key's effect at once
        }
        if (terminal.resized()) {
            shown.reset();
            next_frame = steady_clock::now();
        }
        if (steady_clock::now() >= next_frame) {
            const auto size = terminal.size();
            auto screen = monitor::render(feed.model(), size.width, size.height, charset);
            terminal.write(monitor::ansi_update(shown ? &*shown : nullptr, screen, color));
            shown = std::move(screen);
            next_frame = std::max(next_frame + kFrameEvery, steady_clock::now());
        }
    }
    return kExitOk;
}

int plain(const MonitorOptions& options, Feed& feed, std::ostream& out,
          const std::function<bool()>& interrupted) {
    const auto deadline = deadline_of(options);
    const auto charset = charset_of(options);
    auto next_block = steady_clock::now() + 300ms;  // let the first samples arrive
    std::uint64_t events_printed = 0;
    while (!interrupted() && steady_clock::now() < deadline) {
        feed.pump(kSlice);
        if (steady_clock::now() >= next_block) {
            const auto model = feed.model();
            out << monitor::render_plain(model, model.events_total - events_printed, charset);
            out.flush();
            events_printed = model.events_total;
            next_block = std::max(next_block + kBlockEvery, steady_clock::now());
        }
    }
    return kExitOk;
}

}  // namespace

int run_monitor(const MonitorOptions& options, std::ostream& out, std::ostream& err,
                const std::function<bool()>& interrupted) {
    Feed feed(options.socket, options.control);
    try {
        feed.open();
    } catch (const client::Error& error) {
        err << "gportctl: " << format_error(error) << "\n";
        return error.transport() ? kExitUnavailable : kExitError;
    }
    int status = kExitOk;
    try {
        status = monitor::full_screen_possible() ? full_screen(options, feed, interrupted)
                                                 : plain(options, feed, out, interrupted);
    } catch (const std::exception& error) {  // the terminal is restored by now
        err << "gportctl: monitor: " << printable(error.what()) << "\n";
        status = kExitError;
    }
    feed.close();
    return status;
}

}  // namespace gport::cli

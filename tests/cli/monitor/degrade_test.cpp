// How the monitor degrades: the title at narrow widths and with long socket
// paths, the last values once gportd is gone, ASCII when the locale is not
// UTF-8.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <optional>
#include <regex>

#include "charset.hpp"
#include "lines.hpp"
#include "model_fixture.hpp"
#include "render.hpp"
#include "text.hpp"
#include "title.hpp"

namespace gport::cli::monitor {
namespace {

using ::testing::EndsWith;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::running_model;
using ::testing::StartsWith;

MonitorModel gimbal1_model() {
    auto model = running_model();
    model.socket = "/run/gport/site-a/gportd-gimbal1.sock";
    model.uptime_ms = 12'300'000;  // 3h 25m
    return model;
}

bool ascii_only(const std::string& text) {
    for (unsigned char c : text) {
        if (c >= 0x80) {
            return false;
        }
    }
    return true;
}

TEST(MonitorTitle, LongSocketAt80KeepsTheFileNameUptimeAndClock) {
    const Screen screen = render(gimbal1_model(), 80, 24);
    const std::string title = screen.row_text(0);
    EXPECT_THAT(title, StartsWith(" gportctl monitor · gportd 0.1.0 · "));
    EXPECT_THAT(title, HasSubstr(" · …/gportd-gimbal1.sock "));  // the directory elided
    EXPECT_THAT(title, EndsWith("up 3h 25m  12:03:04"));
}

TEST(MonitorTitle, ThePathStaysWholeWhenThereIsRoom) {
    const Title title = title_for(gimbal1_model(), 120, false);
    EXPECT_THAT(title.left, EndsWith(" · /run/gport/site-a/gportd-gimbal1.sock"));
    EXPECT_EQ(title.right, "up 3h 25m  12:03:04 ");
}

TEST(MonitorTitle, DropsTheVersionThenTheProgramThenTheUptime) {
    const auto model = gimbal1_model();
    EXPECT_EQ(title_for(model, 80, false).left,
              " gportctl monitor · gportd 0.1.0 · …/gportd-gimbal1.sock");
    EXPECT_EQ(title_for(model, 70, false).left, " gportctl monitor · …/gportd-gimbal1.sock");
    EXPECT_EQ(title_for(model, 70, false).right, "up 3h 25m  12:03:04 ");
    EXPECT_EQ(title_for(model, 50, false).left, " …/gportd-gimbal1.sock");
    EXPECT_EQ(title_for(model, 50, false).right, "up 3h 25m  12:03:04 ");
    EXPECT_EQ(title_for(model, 40, false).left, " …/gportd-gimbal1.sock");
    EXPECT_EQ(title_for(model, 40, false).right, "12:03:04 ");  // the uptime goes first
    EXPECT_EQ(title_for(model, 24, false).left, " …/gportd-gim…");
    EXPECT_EQ(title_for(model, 24, false).right, "12:03:04 ");
    EXPECT_EQ(title_for(model, 12, false).right, "");
}

TEST(MonitorTitle, NeverCutsMidNameWhileTheNameFitsAndAlwaysFits) {
    const auto model = gimbal1_model();
    for (int width = 3; width <= 140; ++width) {
        const Title title = title_for(model, width, false);
        EXPECT_LE(columns(title.left) + 1 + columns(title.right), width) << width;
        if (width >= 32) {
            EXPECT_THAT(title.left, EndsWith("gportd-gimbal1.sock")) << width;
            EXPECT_THAT(title.right, HasSubstr("12:03:04")) << width;
        }
    }
}

TEST(MonitorTitle, AsciiElidesWithDots) {
    EXPECT_EQ(title_for(gimbal1_model(), 70, true).left,
              " gportctl monitor · .../gportd-gimbal1.sock");
}

MonitorModel gone_model() {
    auto model = running_model();
    model.connected = false;
    model.stale_since = "12:03:05";
    model.connection_error =
        "cannot connect to /run/gport/site-a/gportd-gimbal1.sock: No such file or directory";
    return model;
}

// The cell where `text` starts on the screen, if it is there.
std::optional<std::pair<int, int>> find_cell(const Screen& screen, const std::string& text) {
    for (int row = 0; row < screen.height(); ++row) {
        const std::string line = screen.row_text(row);
        const auto at = line.find(text);
        if (at != std::string::npos) {
            return std::pair(row, columns(line.substr(0, at)));
        }
    }
    return std::nullopt;
}

TEST(MonitorStale, LastValuesStayFaintUnderStaleTitles) {
    const Screen screen = render(gone_model(), 80, 24);
    const std::string text = screen.text();
    EXPECT_THAT(text, HasSubstr("Attitude (IMU) · stale"));
    EXPECT_THAT(text, HasSubstr("Angles · stale"));
    EXPECT_THAT(text, HasSubstr("Daemon · stale"));
    for (const std::string value : {"+12.34°", "clients 3", "rec unknown", "roll +12.3°"}) {
        const auto cell = find_cell(screen, value);
        ASSERT_TRUE(cell) << value << "\n" << text;
        EXPECT_TRUE(screen.at(cell->first, cell->second).style.dim) << value;
        EXPECT_EQ(screen.at(cell->first, cell->second).style.fg, Color::kGrey) << value;
    }
    const auto mark = find_cell(screen, "stale");
    ASSERT_TRUE(mark);
    EXPECT_FALSE(screen.at(mark->first, mark->second).style.dim);
    // Live, nothing is faint.
    const Screen live = render(running_model(), 80, 24);
    EXPECT_THAT(live.text(), Not(HasSubstr("stale")));
    const auto imu = find_cell(live, "+12.34°");
    ASSERT_TRUE(imu);
    EXPECT_FALSE(live.at(imu->first, imu->second).style.dim);
}

std::string without_spaces(std::string text) {
    text.erase(std::remove(text.begin(), text.end(), ' '), text.end());
    return text;
}

// The rows under the link line, from "reason" on, hold the whole reason.
void expect_that_reason_is_whole(const Screen& screen) {
    const std::string& reason = gone_model().connection_error;
    ASSERT_THAT(screen.row_text(2), StartsWith(" reason  cannot connect to"));
    std::string shown;
    for (int row = 2; row < 6; ++row) {
        const std::string line = screen.row_text(row);
        if (row > 2 && line.rfind("         ", 0) != 0) {
            break;  // not a continuation row
        }
        shown += line.substr(std::min<std::size_t>(line.size(), 9));
    }
    EXPECT_EQ(without_spaces(shown), without_spaces(reason)) << screen.text();
    EXPECT_THAT(shown, Not(HasSubstr("…")));
}

TEST(MonitorStale, TheReasonShowsWholeOnItsOwnRows) {
    for (int width : {80, 60, 40}) {
        const Screen screen = render(gone_model(), width, 24);
        expect_that_reason_is_whole(screen);
        for (int row = 0; row < screen.height(); ++row) {
            EXPECT_LE(columns(screen.row_text(row)), width);
        }
    }
    // Narrow: the values are marked too.
    EXPECT_THAT(render(gone_model(), 40, 20).text(), HasSubstr("stale   last known values:"));
    // The plain block: the reason whole, the values marked.
    const std::string block = render_plain(gone_model(), 0);
    EXPECT_THAT(block, HasSubstr("reason  " + gone_model().connection_error + "\n"));
    EXPECT_THAT(block, HasSubstr("stale   the values below are from before 12:03:05\n"));
}

TEST(MonitorStale, WrapBreaksAtSpacesAndCutsOnlyLongWords) {
    EXPECT_EQ(wrap("one two three", 7), (std::vector<std::string>{"one two", "three"}));
    EXPECT_EQ(wrap("one two three", 5), (std::vector<std::string>{"one", "two", "three"}));
    EXPECT_EQ(wrap("/a/very/long/path x", 6),
              (std::vector<std::string>{"/a/ver", "y/long", "/path", "x"}));
    EXPECT_EQ(wrap("", 5), (std::vector<std::string>{""}));
    EXPECT_TRUE(wrap("x", 0).empty());
}

TEST(MonitorAscii, NoCharacterOutsideAsciiAtAnySize) {
    auto model = running_model();
    model.attitude->rates = client::Rates{.hall = {.roll = 1, .pitch = 2, .yaw = 3},
                                          .imu = {.x = 0.1, .y = 0.2, .z = 0.3}};
    model.control_requested = true;
    for (const auto& m : {model, gone_model(), gimbal1_model()}) {
        for (const auto& [w, h] : {std::pair(80, 24), std::pair(120, 40), std::pair(40, 12)}) {
            const Screen screen = render(m, w, h, Charset::kAscii);
            EXPECT_TRUE(ascii_only(screen.text())) << screen.text();
            EXPECT_TRUE(ascii_only(ansi_update(nullptr, screen, true)));
        }
        EXPECT_TRUE(ascii_only(render_plain(m, 4, Charset::kAscii)));
    }
}

TEST(MonitorAscii, SaysTheSameInAscii) {
    const Screen screen = render(running_model(), 80, 24, Charset::kAscii);
    const std::string text = screen.text();
    EXPECT_THAT(screen.row_text(0),
                HasSubstr("gportctl monitor - gportd 0.1.0 - /run/gportd.sock"));
    EXPECT_THAT(screen.row_text(1), HasSubstr("link * UP  attitude arriving - last sample 12 ms"));
    EXPECT_THAT(text, HasSubstr("+- Attitude (IMU) ---"));
    EXPECT_THAT(text, HasSubstr("IMU     +12.34d  -30.00d  +45.00d"));
    EXPECT_THAT(text, HasSubstr("speed   yaw +30.0 d/s"));
    EXPECT_THAT(text, HasSubstr("==+=="));  // the aircraft
    EXPECT_THAT(text, HasSubstr("^"));      // the heading pointer
    // The horizon, rolled right by 12°, is drawn with '-' over dotted ground.
    EXPECT_TRUE(std::regex_search(text, std::regex(R"(\|[ .]*-+[ .]*)"))) << text;
    EXPECT_THAT(text, HasSubstr("-...."));
    auto rolled = running_model();
    rolled.attitude->imu.roll = 40;
    EXPECT_THAT(render(rolled, 80, 24, Charset::kAscii).text(), HasSubstr("/"));
    rolled.attitude->imu.roll = -40;
    EXPECT_THAT(render(rolled, 80, 24, Charset::kAscii).text(), HasSubstr("\\"));
}

// LC_ALL for the scope of one check.
class ScopedLcAll {
  public:
    explicit ScopedLcAll(const char* value) {
        if (const char* old = ::getenv("LC_ALL")) {
            old_ = old;
        }
        ::setenv("LC_ALL", value, 1);
    }
    ~ScopedLcAll() {
        if (old_) {
            ::setenv("LC_ALL", old_->c_str(), 1);
        } else {
            ::unsetenv("LC_ALL");
        }
    }
    ScopedLcAll(const ScopedLcAll&) = delete;
    ScopedLcAll& operator=(const ScopedLcAll&) = delete;

  private:
    std::optional<std::string> old_;
};

TEST(MonitorAscii, ChosenFromTheLocalesCodeset) {
    {
        ScopedLcAll lc("C");
        EXPECT_EQ(charset_from_locale(), Charset::kAscii);
    }
    {
        ScopedLcAll lc("POSIX");
        EXPECT_EQ(charset_from_locale(), Charset::kAscii);
    }
    {
        ScopedLcAll lc("C.UTF-8");  // always present on Debian
        EXPECT_EQ(charset_from_locale(), Charset::kUtf8);
    }
    {  // not installed: by its name
        ScopedLcAll lc("xx_YY.UTF-8");
        EXPECT_EQ(charset_from_locale(), Charset::kUtf8);
    }
    {
        ScopedLcAll lc("xx_YY.ISO-8859-1");
        EXPECT_EQ(charset_from_locale(), Charset::kAscii);
    }
}

}  // namespace
}  // namespace gport::cli::monitor

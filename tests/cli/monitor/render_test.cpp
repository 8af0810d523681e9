// The monitor's renderer: what a person sees at 80×24, in a small window,
// and in the plain status block; the ANSI output with and without colour.
#include "render.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <regex>

#include "attitude_view.hpp"
#include "model_fixture.hpp"

namespace gport::cli::monitor {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using testing::running_model;

bool has_braille(const std::string& text) {
    // U+2800..U+28FF: E2 A0..A3 xx
    for (std::size_t i = 0; i + 1 < text.size(); ++i) {
        const auto a = static_cast<unsigned char>(text[i]);
        const auto b = static_cast<unsigned char>(text[i + 1]);
        if (a == 0xE2 && b >= 0xA0 && b <= 0xA3) {
            return true;
        }
    }
    return false;
}

void expect_fits(const Screen& screen, int width, int height) {
    ASSERT_EQ(screen.width(), width);
    ASSERT_EQ(screen.height(), height);
    for (int row = 0; row < height; ++row) {
        EXPECT_LE(columns(screen.row_text(row)), width) << "row " << row;
    }
}

TEST(MonitorRender, FullScreenAt80x24ShowsEverything) {
    const Screen screen = render(running_model(), 80, 24);
    expect_fits(screen, 80, 24);
    const std::string text = screen.text();
    EXPECT_THAT(screen.row_text(0),
                HasSubstr("gportctl monitor · gportd 0.1.0 · /run/gportd.sock"));
    EXPECT_THAT(screen.row_text(0), HasSubstr("up 1h 02m  12:03:04"));
    EXPECT_THAT(screen.row_text(1),
                HasSubstr("link ● UP  attitude arriving · last sample 12 ms ago"));
    // Angles with units, both sensors.
    EXPECT_THAT(text, HasSubstr("IMU     +12.34°  -30.00°  +45.00°"));
    EXPECT_THAT(text, HasSubstr("hall    +12.30°  -29.90°  +44.80°"));
    EXPECT_THAT(text, HasSubstr("rates   not sent by this gimbal"));
    // The attitude indicator: braille horizon, roll/pitch, heading tape.
    EXPECT_TRUE(has_braille(text));
    EXPECT_THAT(text, HasSubstr("roll +12.3°  pitch -30.0°"));
    EXPECT_THAT(text, HasSubstr("yaw +45.0°"));
    EXPECT_THAT(text, HasSubstr("▲"));
    // Motion, last end, control, counters.
    EXPECT_THAT(text, HasSubstr("speed   yaw +30.0 °/s"));
    EXPECT_THAT(text, HasSubstr("owner   pid 812 (client 4) · 1.4 s left"));
    EXPECT_THAT(text, HasSubstr("ended   angle: reached at 12:02:58"));
    EXPECT_THAT(text, HasSubstr("control free (last command wins)"));
    EXPECT_THAT(text, HasSubstr("frames  186150 (50/s)  crc 3  resync 1"));
    EXPECT_THAT(text, HasSubstr("drops   7 (you 2)  clients 3  rec unknown"));
    // Events, the newest last, and the keys on the bottom row.
    EXPECT_THAT(text, HasSubstr("12:02:50  link up: attitude arriving"));
    EXPECT_THAT(text, HasSubstr("12:03:03  speed started by pid 812"));
    EXPECT_THAT(screen.row_text(23), HasSubstr("q quit  c centre  arrows nudge with --control"));
}

TEST(MonitorRender, RatesWhenTheGimbalSendsThem) {
    auto model = running_model();
    model.attitude->rates = client::Rates{.hall = {.roll = 1.25, .pitch = -0.5, .yaw = 30},
                                          .imu = {.x = 0.12, .y = -2.3, .z = 0}};
    const std::string text = render(model, 80, 24).text();
    EXPECT_THAT(text, HasSubstr("rate     +1.25    -0.50   +30.00 °/s"));
    EXPECT_THAT(text, HasSubstr("IMU ω   x +0.1 y -2.3 z +0.0 °/s"));
}

TEST(MonitorRender, SmallWindowGetsTheNarrowLayout) {
    const Screen screen = render(running_model(), 40, 12);
    expect_fits(screen, 40, 12);
    const std::string text = screen.text();
    EXPECT_FALSE(has_braille(text));
    EXPECT_THAT(screen.row_text(1), HasSubstr("link ● UP"));
    EXPECT_THAT(text, HasSubstr("IMU     r +12.3 p -30.0 y +45.0 °"));
    EXPECT_THAT(text, HasSubstr("hall    r +12.3 p -29.9 y +44.8 °"));
    EXPECT_THAT(text, HasSubstr("speed   yaw +30.0 °/s"));
    EXPECT_THAT(screen.row_text(11), HasSubstr("q quit"));
}

TEST(MonitorRender, TooSmallSaysSo) {
    const Screen screen = render(running_model(), 20, 4);
    expect_fits(screen, 20, 4);
    EXPECT_THAT(screen.text(), HasSubstr("too small: 20x4"));
}

TEST(MonitorRender, EveryWidthAndHeightFits) {
    for (int width = 1; width <= 120; width += 7) {
        for (int height = 1; height <= 40; height += 3) {
            expect_fits(render(running_model(), width, height), width, height);
        }
    }
}

TEST(MonitorRender, DisconnectedAndLinkDown) {
    auto model = running_model();
    model.link_state = "down";
    model.link_reason = "device vanished";
    EXPECT_THAT(render(model, 80, 24).row_text(1), HasSubstr("link ● DOWN  device vanished"));
    model.connected = false;
    model.connection_error = "cannot connect to /run/gportd.sock: No such file or directory";
    model.stale_since = "12:03:01";
    const Screen screen = render(model, 80, 24);
    EXPECT_THAT(screen.row_text(1),
                HasSubstr("daemon ✖ NOT CONNECTED  since 12:03:01 · retrying every second"));
    EXPECT_THAT(screen.row_text(2),
                HasSubstr("reason  cannot connect to /run/gportd.sock: No such file or directory"));
}

TEST(MonitorRender, ControlKeysShowWhoHoldsControl) {
    auto model = running_model();
    model.control_requested = true;
    model.holds_control = true;
    EXPECT_THAT(render(model, 80, 24).row_text(23),
                HasSubstr("←→ yaw  ↑↓ pitch (20 °/s)  control: you"));
}

// The row of the horizon line in the indicator's column `col`.
int horizon_row(double roll, double pitch, int col) {
    Screen screen(32, 10);
    draw_horizon(screen, Box{0, 0, 32, 10}, roll, pitch);
    for (int row = 0; row < 10; ++row) {
        if (screen.at(row, col).style.bold && screen.at(row, col).glyph != " ") {
            return row;
        }
    }
    return -1;
}

TEST(MonitorRender, HorizonMovesWithPitchAndTiltsWithRoll) {
    const int level = horizon_row(0, 0, 2);
    ASSERT_GE(level, 0);
    EXPECT_GT(horizon_row(0, 20, 2), level);  // nose up: the horizon goes down
    EXPECT_LT(horizon_row(0, -20, 2), level);
    // Rolled right: the horizon's right side rises.
    EXPECT_LT(horizon_row(20, 0, 29), horizon_row(20, 0, 2));
}

TEST(MonitorRender, HeadingTapeLabelsWrap) {
    Screen screen(32, 2);
    draw_heading_tape(screen, Box{0, 0, 32, 2}, 185);
    EXPECT_THAT(screen.row_text(1), HasSubstr("yaw +185.0°"));
    EXPECT_THAT(screen.row_text(1), HasSubstr("-150"));  // 210° shown as -150
    EXPECT_DOUBLE_EQ(wrap_degrees(190), -170);
    EXPECT_DOUBLE_EQ(wrap_degrees(-180), 180);
}

const std::regex kSgr("\x1b\\[[0-9;]*m");

TEST(MonitorRender, NoColourMeansNoSgrSequences) {
    const Screen screen = render(running_model(), 80, 24);
    const std::string plain = ansi_update(nullptr, screen, false);
    EXPECT_FALSE(std::regex_search(plain, kSgr));
    EXPECT_THAT(plain, HasSubstr("\x1b[H"));  // cursor moves only
    const std::string coloured = ansi_update(nullptr, screen, true);
    EXPECT_TRUE(std::regex_search(coloured, kSgr));
    EXPECT_THAT(coloured, HasSubstr("\x1b[0;32;1m● UP"));
}

TEST(MonitorRender, UpdatesRewriteOnlyChangedRows) {
    auto model = running_model();
    const Screen first = render(model, 80, 24);
    EXPECT_EQ(ansi_update(&first, first, true), "");
    model.attitude_age_ms = 48;
    const Screen second = render(model, 80, 24);
    const std::string update = ansi_update(&first, second, false);
    EXPECT_THAT(update, HasSubstr("\x1b[2;1H"));  // the link row
    EXPECT_THAT(update, HasSubstr("last sample 48 ms ago"));
    EXPECT_THAT(update, Not(HasSubstr("\x1b[1;1H")));
    EXPECT_THAT(update, Not(HasSubstr("\x1b[2J")));
    // Another size: the whole screen again.
    EXPECT_THAT(ansi_update(&first, render(model, 100, 30), false), HasSubstr("\x1b[2J"));
}

TEST(MonitorRender, PlainBlockHasNoEscapes) {
    const std::string block = render_plain(running_model(), 2);
    EXPECT_EQ(block.find('\x1b'), std::string::npos);
    EXPECT_THAT(block, HasSubstr("gportctl monitor 12:03:04 · /run/gportd.sock · gportd 0.1.0\n"));
    EXPECT_THAT(block, HasSubstr("link ● UP  attitude arriving · last sample 12 ms ago"));
    EXPECT_THAT(block, HasSubstr("IMU     +12.34°  -30.00°  +45.00°\n"));
    EXPECT_THAT(block, HasSubstr("speed   yaw +30.0 °/s\n"));
    // Only the two newest events.
    EXPECT_THAT(block, Not(HasSubstr("link up: attitude arriving")));
    EXPECT_THAT(block, HasSubstr("event  12:02:58  angle ended: reached\n"));
    EXPECT_THAT(block, HasSubstr("event  12:03:03  speed started"));
    EXPECT_EQ(block.substr(block.size() - 2), "\n\n");
}

}  // namespace
}  // namespace gport::cli::monitor

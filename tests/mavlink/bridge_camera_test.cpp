// The camera component's pure parts (camera.hpp): what it answers, which
// IMAGE_START_CAPTURE parameters it takes, the earth-frame orientation and
// the position of CAMERA_IMAGE_CAPTURED, the capture's meta, and the
// images kept for a ground station that missed one.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "gport/mavlink/attitude.hpp"
#include "gport/mavlink/bridge/camera.hpp"
#include "gport/mavlink/bridge/image_history.hpp"
#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {
namespace {

CommandLong command(std::uint16_t id, std::array<float, 7> params = {}) {
    CommandLong c;
    c.command = id;
    c.param = params;
    return c;
}

client::AttitudeSample sample(double roll, double pitch, double hall_yaw) {
    client::AttitudeSample s;
    s.imu = {roll, pitch, 123.0};  // the IMU's yaw drifts: never used
    s.hall = {0.0, 0.0, hall_yaw};
    return s;
}

TEST(Camera, BadIntervalParametersAreRefusedNamingWhatIsAllowed) {
    const float nan = std::nanf("");
    for (const auto& params : {std::array<float, 7>{0, 1, -1},
                               {0, 1, 2.5F},
                               {0, 1, nan},
                               {0, 0.1F, 5},
                               {0, 0, 0},
                               {0, nan, 3},
                               {0, 4000, 2}}) {
        const auto plan = plan_images(command(mav_cmd::kImageStartCapture, params));
        ASSERT_TRUE(std::holds_alternative<std::string>(plan)) << params[1] << " " << params[2];
        EXPECT_NE(std::get<std::string>(plan).find("allowed"), std::string::npos);
    }
}

TEST(Camera, OneImageOrAnIntervalCapture) {
    const auto single = plan_images(command(mav_cmd::kImageStartCapture, {0, 0, 1}));
    ASSERT_TRUE(std::holds_alternative<ImagePlan>(single));
    EXPECT_EQ(std::get<ImagePlan>(single).count, 1U);
    const auto three = std::get<ImagePlan>(plan_images(command(2000, {0, 1, 3})));
    EXPECT_EQ(three.count, 3U);
    EXPECT_DOUBLE_EQ(three.interval_s, 1.0);
    EXPECT_EQ(std::get<ImagePlan>(plan_images(command(2000, {0, 0.5F, 0}))).count, 0U);
}

TEST(Camera, BroadcastCommandsItTakesAndTheMessagesItServes) {
    EXPECT_TRUE(is_camera_command(command(mav_cmd::kImageStartCapture)));
    EXPECT_TRUE(is_camera_command(command(mav_cmd::kDoDigicamControl)));
    EXPECT_TRUE(is_camera_command(command(mav_cmd::kRequestMessage, {259})));
    EXPECT_TRUE(is_camera_command(command(mav_cmd::kRequestMessage, {262})));
    EXPECT_TRUE(is_camera_command(command(mav_cmd::kRequestMessage, {263})));   // a missed image
    EXPECT_FALSE(is_camera_command(command(mav_cmd::kRequestMessage, {283})));  // the gimbal's
    EXPECT_FALSE(is_camera_command(command(mav_cmd::kRequestMessage, {0})));
    EXPECT_FALSE(is_camera_command(command(mav_cmd::kRequestMessage, {259.5F})));
    EXPECT_FALSE(is_camera_command(command(mav_cmd::kRequestMessage, {-1})));
    EXPECT_FALSE(is_camera_command(command(400)));  // ARM_DISARM
    EXPECT_EQ(requested_message(command(mav_cmd::kRequestCameraInformation, {1})), 259U);
    EXPECT_EQ(requested_message(command(mav_cmd::kRequestCameraCaptureStatus, {1})), 262U);
    EXPECT_EQ(requested_message(command(mav_cmd::kRequestStorageInformation)), 261U);
    EXPECT_FALSE(requested_message(command(mav_cmd::kImageStartCapture)));
}

TEST(ImageHistory, TheCameraProtocolsRangesAndNothingElse) {
    const auto range = [](float first, float last) {
        return image_range(command(mav_cmd::kRequestMessage, {263, first, last}));
    };
    const auto is = [](const std::optional<ImageRange>& r, std::int32_t first,
                       std::optional<std::int32_t> last) {
        return r && r->first == first && r->last == last;
    };
    EXPECT_TRUE(is(range(7, 0), 7, 7));              // that one
    EXPECT_TRUE(is(range(7, -1), 7, std::nullopt));  // it and all after
    EXPECT_TRUE(is(range(7, 9), 7, 9));
    EXPECT_TRUE(is(range(-1, 0), 0, std::nullopt));  // every image
    EXPECT_FALSE(range(7, 6)) << "a last before the first";
    EXPECT_FALSE(range(7.5F, 0));
    EXPECT_FALSE(range(-2, 0));
    EXPECT_FALSE(range(NAN, 0));
    EXPECT_FALSE(range(7, INFINITY));
    EXPECT_TRUE(is(range(2147483648.0F, 0), 2147483647, 2147483647)) << "clamped, not UB";
}

CameraImageCaptured image(std::int32_t index) {
    CameraImageCaptured m;
    m.image_index = index;
    m.lat = 473977420 + index;
    return m;
}

TEST(ImageHistory, KeepsTheNewestAsSentAndFindsARangeWithinItsLimit) {
    ImageHistory history(4);
    history.add(image(-1));  // a failed photo: no index to ask for
    for (std::int32_t i = 0; i < 6; ++i) {
        history.add(image(i));
    }
    EXPECT_EQ(history.size(), 4U);
    const auto indexes = [](const std::vector<CameraImageCaptured>& found) {
        std::vector<std::int32_t> out;
        for (const auto& m : found) {
            out.push_back(m.image_index);
        }
        return out;
    };
    EXPECT_EQ(indexes(history.find({3, 3}, 64)), std::vector<std::int32_t>{3});
    EXPECT_EQ(history.find({3, 3}, 64)[0].lat, 473977423) << "as first sent";
    EXPECT_TRUE(history.find({1, 1}, 64).empty()) << "older than the newest four";
    EXPECT_EQ(indexes(history.find({0, std::nullopt}, 64)),
              (std::vector<std::int32_t>{2, 3, 4, 5}));
    EXPECT_EQ(indexes(history.find({0, std::nullopt}, 3)), (std::vector<std::int32_t>{2, 3, 4}));
    EXPECT_EQ(indexes(history.find({3, 4}, 64)), (std::vector<std::int32_t>{3, 4}));
    EXPECT_TRUE(history.find({6, std::nullopt}, 64).empty()) << "not taken yet";
    history.add(image(1));  // the count restarted (its file lost): the newer ones go
    EXPECT_EQ(indexes(history.find({0, std::nullopt}, 64)), std::vector<std::int32_t>{1});
}

TEST(Camera, InformationSaysWhatIsKnownAndNaNOrZeroForTheRest) {
    const auto info = make_camera_information(5, 154);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(info.vendor_name.data())), "HEQUAV");
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(info.model_name.data())), "G-Port");
    EXPECT_EQ(info.flags, camera_cap::kCaptureImage | camera_cap::kCaptureVideo);
    EXPECT_EQ(info.gimbal_device_id, 154);
    EXPECT_TRUE(std::isnan(info.focal_length) && std::isnan(info.sensor_size_h) &&
                std::isnan(info.sensor_size_v));
    EXPECT_EQ(info.resolution_h, 0);
    EXPECT_EQ(info.cam_definition_uri[0], '\0');
    EXPECT_EQ(make_storage_information(1).status, 0);
}

TEST(Camera, CaptureStatusOfIntervalPhotoAndVideo) {
    CaptureState state;
    EXPECT_EQ(make_capture_status(0, state).image_status, 0);
    state.photo_in_flight = true;
    EXPECT_EQ(make_capture_status(0, state).image_status, 1);
    state.interval_s = 2.0;
    const auto both = make_capture_status(0, state);
    EXPECT_EQ(both.image_status, 3);
    EXPECT_FLOAT_EQ(both.image_interval, 2.0F);
    EXPECT_EQ(both.video_status, 0);
    state.recording_for = std::chrono::milliseconds(1500);
    state.image_count = 4;
    const auto video = make_capture_status(0, state);
    EXPECT_EQ(video.video_status, 1);
    EXPECT_EQ(video.recording_time_ms, 1500U);
    EXPECT_EQ(video.image_count, 4);
}

TEST(Camera, OrientationIsImuRollPitchAndVehiclePlusHallYaw) {
    const auto q = camera_orientation(sample(2, -30, 170), 20.0, Invert{});
    const auto e = *to_euler(q, "q");
    EXPECT_NEAR(e.roll, 2, 1e-3);
    EXPECT_NEAR(e.pitch, -30, 1e-3);
    EXPECT_NEAR(e.yaw, -170, 1e-3);  // 170 + 20, wrapped
    const auto inverted =
        *to_euler(camera_orientation(sample(0, -30, 10), 0.0, {false, true, true}), "q");
    EXPECT_NEAR(inverted.pitch, 30, 1e-3);
    EXPECT_NEAR(inverted.yaw, -10, 1e-3);
    const auto no_vehicle = *to_euler(camera_orientation(sample(0, 10, 15), std::nullopt, {}), "q");
    EXPECT_NEAR(no_vehicle.yaw, 15, 1e-3);
    EXPECT_TRUE(is_nan(camera_orientation(std::nullopt, 20.0, {})));
}

TEST(Camera, ImageCapturedCarriesThePositionOrZeros) {
    GlobalPositionInt p;
    p.lat = -353632621;
    p.lon = 1491652374;
    p.alt = 584070;
    p.relative_alt = -1250;
    ImageCapture capture;
    capture.success = true;
    capture.image_index = 7;
    capture.time_utc_us = 1764000000000000ULL;
    capture.position = p;
    const auto m = make_image_captured(capture);
    EXPECT_EQ(m.capture_result, 1);
    EXPECT_EQ(m.image_index, 7);
    EXPECT_EQ(m.lat, p.lat);
    EXPECT_EQ(m.relative_alt, -1250);
    capture.position.reset();
    capture.success = false;
    const auto none = make_image_captured(capture);
    EXPECT_EQ(none.capture_result, 0);
    EXPECT_EQ(none.lat, 0);
    EXPECT_EQ(none.alt, 0);
}

TEST(Camera, MetaIsTheCompactJsonPositionInDegreesAndMetres) {
    EXPECT_EQ(position_meta(std::nullopt), "");
    GlobalPositionInt p;
    p.lat = -353632621;
    p.lon = 1491652374;
    p.alt = 584070;
    p.relative_alt = -1250;
    const auto text = position_meta(p);
    EXPECT_LE(text.size(), 1024U);
    const auto meta = nlohmann::json::parse(text);
    EXPECT_DOUBLE_EQ(meta.at("lat").get<double>(), -35.3632621);
    EXPECT_DOUBLE_EQ(meta.at("lon").get<double>(), 149.1652374);
    EXPECT_DOUBLE_EQ(meta.at("alt_m").get<double>(), 584.07);
    EXPECT_DOUBLE_EQ(meta.at("relative_alt_m").get<double>(), -1.25);
}

}  // namespace
}  // namespace gport::mavlink::bridge

namespace gport::mavlink::bridge {
namespace {

// Issue 31: CAMERA_IMAGE_CAPTURED's q from the attitude gportd logged for
// that capture, the bridge's own sample only without one.
TEST(CaptureSample, TheLoggedAttitudeWinsOverTheBridgesSample) {
    client::AttitudeSample own;
    own.imu = {0, -10, 0};
    own.hall = {0, -10, 5};
    const client::CaptureAttitude logged{{1, -30, 0}, {0, -30, 20}, 12};
    const auto used = capture_sample(logged, own);
    ASSERT_TRUE(used);
    EXPECT_EQ(used->imu.pitch, -30);
    EXPECT_EQ(used->hall.yaw, 20);
    const auto q = camera_orientation(used, 90.0, {});
    const auto euler = to_euler(q, "q");
    ASSERT_TRUE(euler);
    EXPECT_NEAR(euler->pitch, -30, 1e-3);
    EXPECT_NEAR(euler->yaw, 110, 1e-3);
    EXPECT_EQ(capture_sample(std::nullopt, own)->imu.pitch, -10);
    EXPECT_FALSE(capture_sample(std::nullopt, std::nullopt));
}

}  // namespace
}  // namespace gport::mavlink::bridge

#include "gport/mavlink/crc.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "gport/mavlink/fields.hpp"
#include "gport/mavlink/messages.hpp"

namespace gm = gport::mavlink;

namespace {

std::vector<std::uint8_t> bytes_of(std::string_view s) {
    return {s.begin(), s.end()};
}

TEST(MavlinkCrc, CheckValueOfMcrf4xx) {
    // The catalogue's check value of CRC-16/MCRF4XX over "123456789".
    EXPECT_EQ(gm::crc_calculate(bytes_of("123456789")), 0x6F91);
}

TEST(MavlinkCrc, EmptyInputIsTheInitialValue) {
    EXPECT_EQ(gm::crc_calculate({}), 0xFFFF);
}

TEST(MavlinkCrc, AccumulatesAcrossCalls) {
    const auto all = bytes_of("123456789");
    const std::uint16_t first = gm::crc_calculate(std::span(all).first(4));
    EXPECT_EQ(gm::crc_accumulate(std::span(all).subspan(4), first), 0x6F91);
}

TEST(MavlinkCrc, ChecksumOfAHeartbeatFrameFromNodeMavlink) {
    // Bytes node-mavlink 2.3.0 serialises for HEARTBEAT type 2, autopilot 3,
    // base_mode 0x51, status 4, sysid 1, compid 1, seq 0: checksum 0x1EE7.
    const std::array<std::uint8_t, 21> frame{0xfd, 0x09, 0x00, 0x00, 0x00, 0x01, 0x01,
                                             0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                                             0x02, 0x03, 0x51, 0x04, 0x03, 0xe7, 0x1e};
    std::uint16_t crc = gm::crc_calculate(std::span(frame).subspan(1, 18));
    crc = gm::crc_accumulate(std::uint8_t{50}, crc);
    EXPECT_EQ(crc, 0x1EE7);
}

TEST(MavlinkCrc, CrcExtraOfEveryMessageIsThePublishedValue) {
    // Computed from the field tables; the published values are those of the
    // generated MAVLink headers (and node-mavlink's MSG_ID_MAGIC_NUMBER).
    EXPECT_EQ(gm::crc_extra_of("HEARTBEAT", gm::Heartbeat::kFields), 50);
    EXPECT_EQ(gm::crc_extra_of("COMMAND_LONG", gm::CommandLong::kFields), 152);
    EXPECT_EQ(gm::crc_extra_of("COMMAND_ACK", gm::CommandAck::kFields), 143);
    EXPECT_EQ(gm::crc_extra_of("GIMBAL_DEVICE_INFORMATION", gm::GimbalDeviceInformation::kFields),
              74);
    EXPECT_EQ(gm::crc_extra_of("GIMBAL_DEVICE_SET_ATTITUDE", gm::GimbalDeviceSetAttitude::kFields),
              99);
    EXPECT_EQ(
        gm::crc_extra_of("GIMBAL_DEVICE_ATTITUDE_STATUS", gm::GimbalDeviceAttitudeStatus::kFields),
        137);
    EXPECT_EQ(gm::crc_extra_of("AUTOPILOT_STATE_FOR_GIMBAL_DEVICE",
                               gm::AutopilotStateForGimbalDevice::kFields),
              210);
    // The camera's and the vehicle position's (common.xml; node-mavlink's
    // MAGIC_NUMBERs agree).
    EXPECT_EQ(gm::crc_extra_of("ATTITUDE", gm::Attitude::kFields), 39);
    EXPECT_EQ(gm::crc_extra_of("GLOBAL_POSITION_INT", gm::GlobalPositionInt::kFields), 104);
    EXPECT_EQ(gm::crc_extra_of("SYSTEM_TIME", gm::SystemTime::kFields), 137);
    EXPECT_EQ(gm::crc_extra_of("GPS_RAW_INT", gm::GpsRawInt::kFields), 24);
    EXPECT_EQ(gm::crc_extra_of("CAMERA_INFORMATION", gm::CameraInformation::kFields), 92);
    EXPECT_EQ(gm::crc_extra_of("CAMERA_SETTINGS", gm::CameraSettings::kFields), 146);
    EXPECT_EQ(gm::crc_extra_of("STORAGE_INFORMATION", gm::StorageInformation::kFields), 179);
    EXPECT_EQ(gm::crc_extra_of("CAMERA_CAPTURE_STATUS", gm::CameraCaptureStatus::kFields), 12);
    EXPECT_EQ(gm::crc_extra_of("CAMERA_IMAGE_CAPTURED", gm::CameraImageCaptured::kFields), 133);
}

TEST(MavlinkCrc, ExtensionsDoNotChangeTheCrcExtra) {
    std::vector<gm::FieldSpec> fields(gm::CommandAck::kFields.begin(),
                                      gm::CommandAck::kFields.begin() + 2);
    EXPECT_EQ(gm::crc_extra_of("COMMAND_ACK", fields), 143);
}

TEST(MavlinkCrc, TableLengthsMatchTheDefinitions) {
    struct Row {
        std::uint32_t id;
        std::size_t base;
        std::size_t full;
    };
    for (const Row& r : {Row{0, 9, 9}, Row{76, 33, 33}, Row{77, 3, 10}, Row{283, 144, 149},
                         Row{284, 32, 32}, Row{285, 40, 49}, Row{286, 53, 57}, Row{30, 28, 28},
                         Row{33, 28, 28}, Row{259, 235, 237}, Row{260, 5, 14}, Row{261, 27, 61},
                         Row{262, 18, 23}, Row{263, 255, 255}, Row{2, 12, 12}, Row{24, 30, 52}}) {
        const gm::MessageInfo* info = gm::find_message(r.id);
        ASSERT_NE(info, nullptr) << r.id;
        EXPECT_EQ(info->base_length, r.base) << info->name;
        EXPECT_EQ(info->full_length, r.full) << info->name;
    }
    EXPECT_EQ(gm::message_table().size(), 16U);
    EXPECT_EQ(gm::find_message(31), nullptr);  // ATTITUDE_QUATERNION: not decoded
}

}  // namespace

// gport-mavlink's signing files (signing_files.hpp): the key file refused
// when others could read or change it, or when it is anything but 64 hex
// digits; the timestamp file written whole and read back strictly.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "gport/mavlink/bridge/image_count.hpp"
#include "gport/mavlink/bridge/signing_files.hpp"
#include "signing_samples.hpp"

namespace gport::mavlink::bridge {
namespace {

namespace fs = std::filesystem;

class SigningFiles : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("gport-mavlink-signing-" + std::to_string(::getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string key_file(const std::string& text, mode_t mode) {
        const auto path = (dir_ / "mavlink.key").string();
        std::ofstream(path, std::ios::trunc) << text;
        ::chmod(path.c_str(), mode);
        return path;
    }

    fs::path dir_;
};

const std::string kKey(testing::kNodeKeyHex);

TEST_F(SigningFiles, Mode0600And0400AreAccepted) {
    for (mode_t mode : {0600, 0400}) {
        const auto key = load_signing_key(key_file(kKey + "\n", mode));
        ASSERT_TRUE(key) << key.error().message;
        EXPECT_EQ(key->bytes()[0], 0x6b);
    }
}

// Run as root, a 0600 key owned by another user (who may change it) was
// accepted; now only the effective user's or root's.
TEST_F(SigningFiles, AKeyOwnedByAnotherUserIsRefused) {
    if (::geteuid() != 0) {
        GTEST_SKIP() << "needs root to give the file to another uid (65534)";
    }
    const auto path = key_file(kKey, 0600);
    ASSERT_EQ(::chown(path.c_str(), 65534, 65534), 0);
    const auto key = load_signing_key(path);
    ASSERT_FALSE(key);
    EXPECT_NE(key.error().message.find(path), std::string::npos);
    EXPECT_NE(key.error().message.find("owned by uid 65534"), std::string::npos)
        << key.error().message;
    EXPECT_EQ(key.error().message.find(kKey), std::string::npos);
    ASSERT_EQ(::chown(path.c_str(), 0, 0), 0);
    EXPECT_TRUE(load_signing_key(path)) << "root's own file";
}

TEST_F(SigningFiles, SurroundingWhitespaceIsAllowed) {
    EXPECT_TRUE(load_signing_key(key_file("  \n\t" + kKey + " \r\n\n", 0600)));
}

TEST_F(SigningFiles, GroupOrWorldPermissionsAreRefusedNamingFileAndMode) {
    for (mode_t mode : {0640, 0604, 0620, 0602, 0660, 0644, 0610}) {
        const auto path = key_file(kKey, mode);
        const auto key = load_signing_key(path);
        ASSERT_FALSE(key) << std::oct << mode;
        const auto& text = key.error().message;
        EXPECT_NE(text.find(path), std::string::npos) << text;
        char octal[8];
        std::snprintf(octal, sizeof octal, "%04o", static_cast<unsigned>(mode));
        EXPECT_NE(text.find(std::string("mode ") + octal), std::string::npos) << text;
        EXPECT_NE(text.find("chmod 600 or 400"), std::string::npos) << text;
    }
    const auto key = load_signing_key(key_file(kKey, 0640));
    EXPECT_NE(key.error().message.find("group-readable"), std::string::npos);
    EXPECT_NE(load_signing_key(key_file(kKey, 0604)).error().message.find("world-readable"),
              std::string::npos);
}

TEST_F(SigningFiles, MalformedKeysAreRefusedWithoutShowingTheKey) {
    std::string bad_hex = kKey;
    bad_hex[5] = 'x';
    for (const std::string& text : {bad_hex, kKey.substr(0, 63), kKey + "0", kKey + " " + kKey,
                                    std::string(""), "key=" + kKey, std::string("passphrase")}) {
        const auto path = key_file(text, 0600);
        const auto key = load_signing_key(path);
        ASSERT_FALSE(key) << text;
        EXPECT_NE(key.error().message.find(path), std::string::npos);
        EXPECT_NE(key.error().message.find("64 hexadecimal digits"), std::string::npos);
        EXPECT_EQ(key.error().message.find(kKey.substr(0, 16)), std::string::npos);
    }
    const auto length = load_signing_key(key_file(kKey.substr(0, 63), 0600));
    EXPECT_NE(length.error().message.find("63 characters"), std::string::npos);
}

TEST_F(SigningFiles, AnOversizedFileIsRefused) {
    const auto key = load_signing_key(key_file(std::string(5000, ' ') + kKey, 0600));
    ASSERT_FALSE(key);
    EXPECT_NE(key.error().message.find("over 1024 bytes"), std::string::npos);
}

TEST_F(SigningFiles, MissingDirectoryAndFifoAreRefused) {
    const auto missing = load_signing_key((dir_ / "absent.key").string());
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("cannot be opened"), std::string::npos);
    const auto directory = load_signing_key(dir_.string());
    ASSERT_FALSE(directory);
    EXPECT_NE(directory.error().message.find("not a regular file"), std::string::npos);
    const auto fifo = (dir_ / "fifo").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const auto piped = load_signing_key(fifo);  // must not hang
    ASSERT_FALSE(piped);
    EXPECT_NE(piped.error().message.find("not a regular file"), std::string::npos);
}

TEST_F(SigningFiles, ASymlinkToAGoodKeyIsFollowed) {
    const auto target = key_file(kKey, 0600);
    const auto link = (dir_ / "link.key").string();
    fs::create_symlink(target, link);
    EXPECT_TRUE(load_signing_key(link));
}

TEST_F(SigningFiles, TimestampRoundTripAndFirstStart) {
    const TimestampFile file(dir_.string());
    EXPECT_EQ(file.path(), (dir_ / "signing-timestamp").string());
    const auto first = file.load();
    ASSERT_TRUE(first) << first.error().message;
    EXPECT_EQ(*first, 0U);  // no file yet
    ASSERT_FALSE(file.save(123456789));
    EXPECT_EQ(*file.load(), 123456789U);
    ASSERT_FALSE(file.save(kMaxTimestamp));
    EXPECT_EQ(*file.load(), kMaxTimestamp);
    // Only the file itself: the unique temporary files are renamed or removed.
    for (const auto& entry : fs::directory_iterator(dir_)) {
        EXPECT_EQ(entry.path(), fs::path(file.path())) << "left behind: " << entry.path();
    }
    EXPECT_EQ(fs::status(file.path()).permissions() & fs::perms::others_all, fs::perms::none);
}

TEST_F(SigningFiles, AMalformedTimestampFileStopsTheStart) {
    const TimestampFile file(dir_.string() + "/");
    for (const std::string text : {"", "abc", "12 34", "-5", "281474976710656", "1.5"}) {
        std::ofstream(file.path(), std::ios::trunc) << text;
        const auto value = file.load();
        ASSERT_FALSE(value) << text;
        EXPECT_NE(value.error().message.find(file.path()), std::string::npos);
    }
    std::ofstream(file.path(), std::ios::trunc) << " 42\n";
    EXPECT_EQ(*file.load(), 42U);
}

// Two processes sharing a state directory would overwrite each other's
// timestamp (one's sent timestamps above the other's file): the second is
// refused, naming the directory and what to do. flock locks belong to the
// open file description, so two objects in one process conflict the same.
TEST_F(SigningFiles, ASecondUserOfTheStateDirectoryIsRefused) {
    TimestampFile first(dir_.string());
    ASSERT_FALSE(first.lock());
    TimestampFile second(dir_.string());
    const auto error = second.lock();
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find(dir_.string()), std::string::npos) << error->message;
    EXPECT_NE(error->message.find("in use by another process"), std::string::npos);
    EXPECT_NE(error->message.find("--state-dir"), std::string::npos);
    {
        TimestampFile moved(std::move(first));  // the lock moves with the object
        EXPECT_TRUE(second.lock());
    }
    EXPECT_FALSE(second.lock()) << "released when its holder is gone";
}

TEST_F(SigningFiles, AMissingStateDirectoryCannotBeLocked) {
    TimestampFile file((dir_ / "absent").string());
    const auto error = file.lock();
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("absent"), std::string::npos);
}

TEST_F(SigningFiles, AnUnwritableStateDirectoryIsReported) {
    const TimestampFile file((dir_ / "absent").string());
    const auto error = file.save(1);
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("signing-timestamp"), std::string::npos);
}

// Issue 30, item 2: a state directory that others can write (they could
// plant the timestamp) is refused, naming it, the mode and what to do.
TEST_F(SigningFiles, AStateDirectoryOthersCanWriteIsRefused) {
    for (mode_t mode : {0777, 0775, 0733, 01777}) {
        ASSERT_EQ(::chmod(dir_.c_str(), mode), 0);
        TimestampFile file(dir_.string());
        const auto error = file.lock();
        ASSERT_TRUE(error) << std::oct << mode;
        EXPECT_NE(error->message.find("state directory " + dir_.string()), std::string::npos)
            << error->message;
        EXPECT_NE(error->message.find("-writable"), std::string::npos) << error->message;
        EXPECT_NE(error->message.find("chmod 700"), std::string::npos) << error->message;
    }
    for (mode_t mode : {0700, 0755, 0750}) {
        ASSERT_EQ(::chmod(dir_.c_str(), mode), 0);
        TimestampFile file(dir_.string());
        EXPECT_FALSE(file.lock()) << std::oct << mode;
    }
}

TEST_F(SigningFiles, AStateDirectoryOwnedByAnotherUserIsRefused) {
    if (::geteuid() != 0) {
        GTEST_SKIP() << "needs root to give the directory to another uid (65534)";
    }
    ASSERT_EQ(::chmod(dir_.c_str(), 0700), 0);
    ASSERT_EQ(::chown(dir_.c_str(), 65534, 65534), 0);
    TimestampFile file(dir_.string());
    const auto error = file.lock();
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("owned by uid 65534"), std::string::npos) << error->message;
    ASSERT_EQ(::chown(dir_.c_str(), 0, 0), 0);
    EXPECT_FALSE(file.lock()) << "root's own directory";
}

// A symbolic link in the timestamp file's place is not followed, nor is a
// FIFO read.
TEST_F(SigningFiles, ATimestampFileThatIsALinkOrNoRegularFileIsRefused) {
    const auto target = dir_ / "elsewhere";
    std::ofstream(target) << "42\n";
    const TimestampFile file(dir_.string());
    fs::create_symlink(target, file.path());
    const auto linked = file.load();
    ASSERT_FALSE(linked);
    EXPECT_NE(linked.error().message.find("symbolic link"), std::string::npos)
        << linked.error().message;
    fs::remove(file.path());
    ASSERT_EQ(::mkfifo(file.path().c_str(), 0600), 0);
    const auto piped = file.load();  // must not hang
    ASSERT_FALSE(piped);
    EXPECT_NE(piped.error().message.find("not a regular file"), std::string::npos);
}

}  // namespace
}  // namespace gport::mavlink::bridge

namespace gport::mavlink::bridge {
namespace {

// The image count (image_count.hpp, issue 31): zero-based image_index,
// kept across restarts beside the signing timestamp, under its rules.
TEST_F(SigningFiles, TheImageCountSurvivesARestart) {
    ImageCount first(dir_.string());
    ASSERT_FALSE(first.load());
    EXPECT_TRUE(first.kept());
    EXPECT_EQ(first.count(), 0);
    std::optional<Error> error;
    EXPECT_EQ(first.add(error), 0);  // the first image has index 0, count 1
    EXPECT_EQ(first.add(error), 1);
    EXPECT_FALSE(error);
    EXPECT_EQ(first.count(), 2);
    ImageCount restarted(dir_.string());
    ASSERT_FALSE(restarted.load());
    EXPECT_EQ(restarted.count(), 2);
    EXPECT_EQ(restarted.add(error), 2);  // contiguous: image_count - 1
    EXPECT_EQ(restarted.count(), 3);
}

TEST_F(SigningFiles, WithoutAStateDirectoryTheImageCountIsNotKept) {
    ImageCount count("");
    EXPECT_FALSE(count.load());
    EXPECT_FALSE(count.kept());
    std::optional<Error> error;
    EXPECT_EQ(count.add(error), 0);
    EXPECT_FALSE(error);
}

TEST_F(SigningFiles, TheImageCountFileFollowsTheStateDirectoryRules) {
    const auto file = dir_ / ImageCount::kFileName;
    fs::create_symlink("/etc/hostname", file);
    ImageCount linked(dir_.string());
    auto error = linked.load();
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("symbolic link"), std::string::npos) << error->message;
    EXPECT_EQ(linked.count(), 0);
    fs::remove(file);
    std::ofstream(file) << "twelve\n";
    error = ImageCount(dir_.string()).load();
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("does not hold an image count"), std::string::npos);
    fs::remove(file);
    ::chmod(dir_.c_str(), 0777);
    error = ImageCount(dir_.string()).load();
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("mode 0777"), std::string::npos) << error->message;
    ::chmod(dir_.c_str(), 0700);
}

}  // namespace
}  // namespace gport::mavlink::bridge

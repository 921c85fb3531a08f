// The core's shared helpers: numeric conventions and safe output files.
#include <gtest/gtest.h>

#include "parallaxes/core/siphash.h"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "parallaxes/core/files.h"
#include "parallaxes/core/numeric.h"

namespace px {
namespace {

namespace fs = std::filesystem;

// SipHash-2-4 against the paper's own vectors (Aumasson and Bernstein 2012,
// appendix A: key 00..0f, message 00..0e; and the reference
// implementation's first vector, the empty message under the same key).
TEST(SipHash, MatchesThePublishedVectors) {
    SipKey key{};
    for (int i = 0; i < 16; ++i) key[static_cast<size_t>(i)] = static_cast<std::uint8_t>(i);
    std::uint8_t message[15];
    for (int i = 0; i < 15; ++i) message[i] = static_cast<std::uint8_t>(i);
    EXPECT_EQ(siphash24(key, message, 15), 0xa129ca6149be45e5ull);
    EXPECT_EQ(siphash24(key, message, 0), 0x726fdb47dd0e0e31ull);
    SipKey other = key;
    other[0] ^= 1;
    EXPECT_NE(siphash24(other, message, 15), siphash24(key, message, 15));
}

TEST(Numeric, Unorm8RoundsToNearestAndClamps) {
    EXPECT_EQ(to_unorm8(0.0), 0);
    EXPECT_EQ(to_unorm8(1.0), 255);
    EXPECT_EQ(to_unorm8(0.5), 128);  // 127.5 rounds away from zero, as lround does
    EXPECT_EQ(to_unorm8(-3.0), 0);
    EXPECT_EQ(to_unorm8(7.0), 255);
    EXPECT_EQ(to_unorm8(std::nan("")), 0);
    EXPECT_DOUBLE_EQ(quantize_unorm8(100.0 / 255.0 + 1e-4), 100.0 / 255.0);
}

TEST(Numeric, WrapAndPowerOfTwo) {
    EXPECT_EQ(wrap_index(-1, 8), 7);
    EXPECT_EQ(wrap_index(-8, 8), 0);
    EXPECT_EQ(wrap_index(17, 8), 1);
    EXPECT_TRUE(is_power_of_two(1));
    EXPECT_TRUE(is_power_of_two(1LL << 40));
    EXPECT_FALSE(is_power_of_two(0));
    EXPECT_FALSE(is_power_of_two(-4));
    EXPECT_FALSE(is_power_of_two(12));
}

// GL_LINEAR's taps (ES 3.0, 3.8.10): texel centres at +0.5, wrapping.
TEST(Numeric, BilinearTapsFollowGlLinearWithRepeat) {
    const BilinearTaps centre = bilinear_taps(0.5 / 4, 0.5 / 4, 4, 4);  // texel (0, 0)'s centre
    EXPECT_EQ(centre.x0, 0);
    EXPECT_DOUBLE_EQ(centre.ax, 0.0);
    const BilinearTaps edge = bilinear_taps(0.0, 0.0, 4, 4);  // halfway between texel 3 (wrapped) and 0
    EXPECT_EQ(edge.x0, 3);
    EXPECT_EQ(edge.x1, 0);
    EXPECT_DOUBLE_EQ(edge.ax, 0.5);
    const BilinearTaps huge = bilinear_taps(1e12 + 0.5 / 4, -1e12 + 0.5 / 4, 4, 4);
    EXPECT_GE(huge.x0, 0);
    EXPECT_LT(huge.x0, 4);
    EXPECT_GE(huge.y0, 0);
    EXPECT_LT(huge.y0, 4);
}

class OutputFile : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("px_files_" + std::to_string(::getpid()) + "_" +
                                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::permissions(dir_, fs::perms::owner_all, ec);
        fs::remove_all(dir_, ec);
    }
    static std::string read(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    int entries() const { return static_cast<int>(std::distance(fs::directory_iterator(dir_), {})); }
    fs::path dir_;
};

TEST_F(OutputFile, WritesThenReplacesLeavingNoTemporary) {
    const fs::path out = dir_ / "report.md";
    ASSERT_TRUE(write_file_atomically(out.string(), std::string("first")).ok());
    ASSERT_TRUE(write_file_atomically(out.string(), std::string("second, longer")).ok());
    EXPECT_EQ(read(out), "second, longer");
    EXPECT_EQ(entries(), 1) << "a temporary file was left behind";
}

// A symlink planted at the output path is replaced, never followed: the
// file it points at keeps its content.
TEST_F(OutputFile, ReplacesASymlinkInsteadOfWritingThroughIt) {
    const fs::path victim = dir_ / "victim.txt";
    { std::ofstream(victim) << "precious"; }
    const fs::path out = dir_ / "out.png";
    fs::create_symlink(victim, out);
    ASSERT_TRUE(write_file_atomically(out.string(), std::string("image")).ok());
    EXPECT_EQ(read(victim), "precious");
    EXPECT_FALSE(fs::is_symlink(out));
    EXPECT_EQ(read(out), "image");
}

// `-o /dev/null`, `-o /dev/stdout`, a named pipe: streams are written
// into, never renamed over (as root that put a regular file where
// /dev/null was, 2026-12-05). Through a link here, so that a regression
// replaces the link, not the system's /dev/null.
TEST_F(OutputFile, WritesIntoDevicesAndPipesInsteadOfReplacingThem) {
    const fs::path null_link = dir_ / "discard.png";
    fs::create_symlink("/dev/null", null_link);
    ASSERT_TRUE(write_file_atomically(null_link.string(), std::string("image")).ok());
    EXPECT_TRUE(fs::is_symlink(null_link)) << "the link to /dev/null was replaced";
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    EXPECT_EQ(entries(), 1) << "a temporary file was left behind";

    // A named pipe with a reader gets the bytes; it stays a pipe.
    const fs::path fifo = dir_ / "pipe";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
    ASSERT_GE(reader, 0);
    ASSERT_TRUE(write_file_atomically(fifo.string(), std::string("through the pipe")).ok());
    char got[64] = {};
    EXPECT_EQ(::read(reader, got, sizeof got), 16);
    EXPECT_EQ(std::string(got), "through the pipe");
    ::close(reader);
    EXPECT_TRUE(fs::is_fifo(fifo));
    // Without a reader: refused at once (no wait), still a pipe.
    Status lonely = write_file_atomically(fifo.string(), std::string("x"));
    ASSERT_FALSE(lonely.ok());
    EXPECT_NE(lonely.error().message.find("no reader"), std::string::npos) << lonely.error().message;
    EXPECT_TRUE(fs::is_fifo(fifo));

    // A socket is not an output file, nor replaced by one.
    const fs::path sock = dir_ / "sock";
    const int sd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    ASSERT_GE(sd, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    ASSERT_LT(sock.string().size(), sizeof addr.sun_path);
    std::strcpy(addr.sun_path, sock.c_str());
    ASSERT_EQ(::bind(sd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    Status socket_out = write_file_atomically(sock.string(), std::string("x"));
    ::close(sd);
    ASSERT_FALSE(socket_out.ok());
    EXPECT_NE(socket_out.error().message.find("socket"), std::string::npos) << socket_out.error().message;
    EXPECT_TRUE(fs::is_socket(sock));
    EXPECT_EQ(entries(), 3);
}

// A write-protected file (no write bit for anyone) is refused, even for
// root, and keeps its content.
TEST_F(OutputFile, RefusesAWriteProtectedFile) {
    const fs::path out = dir_ / "locked.png";
    { std::ofstream(out) << "old"; }
    fs::permissions(out, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    Status s = write_file_atomically(out.string(), std::string("new"));
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("write-protected"), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find(out.string()), std::string::npos) << s.error().message;
    EXPECT_EQ(read(out), "old");
    EXPECT_EQ(entries(), 1);
}

TEST_F(OutputFile, MissingFolderAndFolderTargetAreNamed) {
    const fs::path missing = dir_ / "no" / "such" / "out.png";
    Status a = write_file_atomically(missing.string(), std::string("x"));
    ASSERT_FALSE(a.ok());
    EXPECT_NE(a.error().message.find(missing.string()), std::string::npos) << a.error().message;
    Status b = write_file_atomically(dir_.string(), std::string("x"));
    ASSERT_FALSE(b.ok());
    EXPECT_NE(b.error().message.find("folder"), std::string::npos) << b.error().message;
    EXPECT_FALSE(write_file_atomically("", std::string("x")).ok());
}

TEST_F(OutputFile, NewFileGetsTheUmaskModeNotMkstemps) {
    const fs::path out = dir_ / "new.png";
    const mode_t mask = ::umask(022);
    ASSERT_TRUE(write_file_atomically(out.string(), std::string("x")).ok());
    ::umask(mask);
    struct stat st {};
    ASSERT_EQ(::stat(out.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0644u);
}

}  // namespace
}  // namespace px

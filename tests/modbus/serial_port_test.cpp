// firmware/linux/serial_port: pty pair with symlink, raw tty mode, stamped
// non-blocking reads, writes, clean-up.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <string>

#include "serial_port.h"

namespace mb2co {
namespace port {
namespace {

class SerialPortTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char templ[] = "/tmp/mb2co-serial-XXXXXX";
    ASSERT_NE(mkdtemp(templ), nullptr);
    dir_ = templ;
    link_ = dir_ + "/modbus";
  }
  void TearDown() override {
    unlink(link_.c_str());
    rmdir(dir_.c_str());
  }
  static bool readable(int fd, int timeout_ms) {
    pollfd p{fd, POLLIN, 0};
    return poll(&p, 1, timeout_ms) == 1;
  }
  std::string dir_, link_;
};

TEST_F(SerialPortTest, PtyPairCarriesBytesBothWaysWithStamps) {
  SerialPort port;
  ASSERT_TRUE(port.create_pty(link_)) << port.error();
  const int peer = open(link_.c_str(), O_RDWR | O_NOCTTY);
  ASSERT_GE(peer, 0);
  const uint32_t before = monotonic_us();
  ASSERT_EQ(write(peer, "abc", 3), 3);
  ASSERT_TRUE(readable(port.fd(), 2000));
  uint8_t bytes[16];
  uint32_t stamps[16];
  const long n = port.read(bytes, stamps, sizeof bytes);
  const uint32_t after = monotonic_us();
  ASSERT_EQ(n, 3);
  EXPECT_EQ(std::string(bytes, bytes + 3), "abc");
  for (int i = 0; i < 3; ++i) {
    EXPECT_LE(before, stamps[i]);
    EXPECT_LE(stamps[i], after);
  }
  const uint8_t reply[] = {'x', 'y', 'z'};
  ASSERT_TRUE(port.write(reply, 3)) << port.error();
  ASSERT_TRUE(readable(peer, 2000));
  char got[4] = {};
  EXPECT_EQ(read(peer, got, 3), 3);
  EXPECT_STREQ(got, "xyz");
  EXPECT_EQ(port.read(bytes, stamps, sizeof bytes), 0) << "raw mode: nothing echoed back";
  close(peer);
  EXPECT_EQ(port.read(bytes, stamps, sizeof bytes), 0) << "peer hang-up is not an error";
}

TEST_F(SerialPortTest, LinkPointsAtDeviceAndIsRemovedOnClose) {
  SerialPort port;
  ASSERT_TRUE(port.create_pty(link_)) << port.error();
  char target[256] = {};
  ASSERT_GT(readlink(link_.c_str(), target, sizeof target - 1), 0);
  EXPECT_EQ(port.path(), target);
  EXPECT_EQ(port.link_path(), link_);
  port.close();
  struct stat st;
  EXPECT_NE(lstat(link_.c_str(), &st), 0);
  EXPECT_FALSE(port.is_open());
}

TEST_F(SerialPortTest, ReplacesStaleLinkButNoOtherFile) {
  ASSERT_EQ(symlink("/nonexistent", link_.c_str()), 0);
  SerialPort port;
  ASSERT_TRUE(port.create_pty(link_)) << port.error();
  port.close();
  const int f = open(link_.c_str(), O_CREAT | O_WRONLY, 0600);
  ASSERT_GE(f, 0);
  close(f);
  EXPECT_FALSE(port.create_pty(link_));
  EXPECT_NE(port.error().find("refusing"), std::string::npos) << port.error();
  struct stat st;
  ASSERT_EQ(lstat(link_.c_str(), &st), 0);
  EXPECT_TRUE(S_ISREG(st.st_mode)) << "the regular file was left alone";
}

// A pty stands in for the tty: Linux's pty driver forces CS8 and clears
// PARENB whatever is asked, so parity itself is only visible on real ports.
TEST_F(SerialPortTest, OpenTtyConfiguresRawModeBaudAndStopBits) {
  SerialPort pty;
  ASSERT_TRUE(pty.create_pty()) << pty.error();
  SerialPort tty;
  ASSERT_TRUE(tty.open_tty(pty.path(), 19200, Parity::kEven, 2)) << tty.error();
  termios t;
  ASSERT_EQ(tcgetattr(tty.fd(), &t), 0);
  EXPECT_EQ(cfgetospeed(&t), static_cast<speed_t>(B19200));
  EXPECT_EQ(cfgetispeed(&t), static_cast<speed_t>(B19200));
  EXPECT_TRUE(t.c_cflag & CSTOPB);
  EXPECT_TRUE(t.c_cflag & CLOCAL);
  EXPECT_EQ(t.c_cflag & CSIZE, static_cast<tcflag_t>(CS8));
  EXPECT_FALSE(t.c_lflag & (ICANON | ECHO));
  const uint8_t b = 0x7E;
  ASSERT_TRUE(tty.write(&b, 1));
  ASSERT_TRUE(readable(pty.fd(), 2000));
  uint8_t got = 0;
  uint32_t stamp;
  EXPECT_EQ(pty.read(&got, &stamp, 1), 1);
  EXPECT_EQ(got, 0x7E);
}

TEST_F(SerialPortTest, BadArgumentsGiveOneLineErrors) {
  SerialPort port;
  EXPECT_FALSE(port.open_tty("/dev/null-not-there", 9600, Parity::kNone));
  EXPECT_NE(port.error().find("/dev/null-not-there"), std::string::npos);
  EXPECT_FALSE(port.open_tty("/dev/null", 12345, Parity::kNone));
  EXPECT_NE(port.error().find("12345"), std::string::npos);
  EXPECT_FALSE(port.open_tty("/dev/null", 9600, Parity::kNone, 3));
  EXPECT_FALSE(port.create_pty(dir_ + "/no/such/dir/link"));
  EXPECT_FALSE(port.is_open());
  uint8_t b;
  uint32_t s;
  EXPECT_EQ(port.read(&b, &s, 1), -1);
  EXPECT_EQ(port.error().find('\n'), std::string::npos);
}

}  // namespace
}  // namespace port
}  // namespace mb2co

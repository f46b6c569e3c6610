// host/platform/serial_port: pty pair with symlink, raw tty mode, stamped
// non-blocking reads, writes, clean-up.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <string>

#include "platform/serial_port.h"

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

// read() as a count: -1 when it failed (its message in *why).
long read_n(SerialPort& port, uint8_t* bytes, uint32_t* stamps, size_t capacity, std::string* why = nullptr) {
  size_t n = 0;
  const Status done = port.read(bytes, stamps, capacity, &n);
  if (why != nullptr) *why = done.message();
  return done ? static_cast<long>(n) : -1;
}

TEST_F(SerialPortTest, PtyPairCarriesBytesBothWaysWithStamps) {
  SerialPort port;
  const Status opened = port.create_pty(link_);
  ASSERT_TRUE(opened) << opened.message();
  const int peer = open(link_.c_str(), O_RDWR | O_NOCTTY);
  ASSERT_GE(peer, 0);
  const uint32_t before = monotonic_us();
  ASSERT_EQ(write(peer, "abc", 3), 3);
  ASSERT_TRUE(readable(port.fd(), 2000));
  uint8_t bytes[16];
  uint32_t stamps[16];
  const long n = read_n(port, bytes, stamps, sizeof bytes);
  const uint32_t after = monotonic_us();
  ASSERT_EQ(n, 3);
  EXPECT_EQ(std::string(bytes, bytes + 3), "abc");
  for (int i = 0; i < 3; ++i) {
    EXPECT_LE(before, stamps[i]);
    EXPECT_LE(stamps[i], after);
  }
  const uint8_t reply[] = {'x', 'y', 'z'};
  const Status written = port.write(reply, 3);
  ASSERT_TRUE(written) << written.message();
  ASSERT_TRUE(readable(peer, 2000));
  char got[4] = {};
  EXPECT_EQ(read(peer, got, 3), 3);
  EXPECT_STREQ(got, "xyz");
  EXPECT_EQ(read_n(port, bytes, stamps, sizeof bytes), 0) << "raw mode: nothing echoed back";
  close(peer);
  EXPECT_EQ(read_n(port, bytes, stamps, sizeof bytes), 0) << "peer hang-up is not an error";
}

TEST_F(SerialPortTest, LinkPointsAtDeviceAndIsRemovedOnClose) {
  SerialPort port;
  const Status opened = port.create_pty(link_);
  ASSERT_TRUE(opened) << opened.message();
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
  const Status opened = port.create_pty(link_);
  ASSERT_TRUE(opened) << opened.message();
  port.close();
  const int f = open(link_.c_str(), O_CREAT | O_WRONLY, 0600);
  ASSERT_GE(f, 0);
  close(f);
  const Status refused = port.create_pty(link_);
  EXPECT_FALSE(refused);
  EXPECT_NE(refused.message().find("refusing"), std::string::npos) << refused.message();
  struct stat st;
  ASSERT_EQ(lstat(link_.c_str(), &st), 0);
  EXPECT_TRUE(S_ISREG(st.st_mode)) << "the regular file was left alone";
}

// A pty stands in for the tty: Linux's pty driver forces CS8 and clears
// PARENB whatever is asked, so parity itself is only visible on real ports.
TEST_F(SerialPortTest, OpenTtyConfiguresRawModeBaudAndStopBits) {
  SerialPort pty;
  const Status pty_opened = pty.create_pty();
  ASSERT_TRUE(pty_opened) << pty_opened.message();
  SerialPort tty;
  const Status tty_opened = tty.open_tty(pty.path(), 19200, modbus::Parity::kEven, 2);
  ASSERT_TRUE(tty_opened) << tty_opened.message();
  termios t;
  ASSERT_EQ(tcgetattr(tty.fd(), &t), 0);
  EXPECT_EQ(cfgetospeed(&t), static_cast<speed_t>(B19200));
  EXPECT_EQ(cfgetispeed(&t), static_cast<speed_t>(B19200));
  EXPECT_TRUE(t.c_cflag & CSTOPB);
  EXPECT_TRUE(t.c_cflag & CLOCAL);
  EXPECT_EQ(t.c_cflag & CSIZE, static_cast<tcflag_t>(CS8));
  EXPECT_FALSE(t.c_lflag & (ICANON | ECHO));
  const uint8_t b = 0x7E;
  ASSERT_TRUE(tty.write(&b, 1).is_ok());
  ASSERT_TRUE(readable(pty.fd(), 2000));
  uint8_t got = 0;
  uint32_t stamp;
  EXPECT_EQ(read_n(pty, &got, &stamp, 1), 1);
  EXPECT_EQ(got, 0x7E);
}

TEST_F(SerialPortTest, BadArgumentsGiveOneLineErrors) {
  SerialPort port;
  const Status missing = port.open_tty("/dev/null-not-there", 9600, modbus::Parity::kNone);
  EXPECT_FALSE(missing);
  EXPECT_NE(missing.message().find("/dev/null-not-there"), std::string::npos);
  const Status odd_baud = port.open_tty("/dev/null", 12345, modbus::Parity::kNone);
  EXPECT_FALSE(odd_baud);
  EXPECT_NE(odd_baud.message().find("12345"), std::string::npos);
  EXPECT_FALSE(port.open_tty("/dev/null", 9600, modbus::Parity::kNone, 3));
  EXPECT_FALSE(port.create_pty(dir_ + "/no/such/dir/link"));
  EXPECT_FALSE(port.is_open());
  uint8_t b;
  uint32_t s;
  std::string why;
  EXPECT_EQ(read_n(port, &b, &s, 1, &why), -1);
  EXPECT_EQ(why.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace port
}  // namespace mb2co

// npm's canopen SDO client against the real I/O node image (mb2co-ionode.elf
// in mb2co-uno --image ionode) on vcan0 (ctest peers.npm_client_vs_ionode,
// inside hil/uml/run-with-vcan.sh): the CiA 401 input parameters 6002h and
// 6005h-6008h read with the defaults docs/mb2co-ionode.eds gives them; a
// polarity written by npm inverts what npm reads in 6000h; masks written by
// npm decide which joystick changes send TPDO1 (watched on a raw socket).
#include <gtest/gtest.h>
#include <poll.h>

#include "npm_peer.h"
#include "platform/socketcan_port.h"
#include "uno_harness.h"

namespace mb2co {
namespace test {
namespace {

constexpr int kNode = 0x20;  // a fresh I/O node board
const std::string kNodeText = std::to_string(kNode);
constexpr uint16_t kTpdo1 = 0x180 + kNode;

/// npm's upload of INDEX/SUB: the data as hex ("" when it failed).
std::string npm_read(uint16_t index, int sub) {
  char text[8];
  std::snprintf(text, sizeof text, "0x%04X", index);
  const PeerResult r =
      run_peer_client({"upload", "--node", kNodeText, "--index", text, "--sub", std::to_string(sub)});
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  return r.field("data");
}

/// npm's download of one byte.
void npm_write(uint16_t index, int sub, const char* hex) {
  char text[8];
  std::snprintf(text, sizeof text, "0x%04X", index);
  const PeerResult r = run_peer_client(
      {"download", "--node", kNodeText, "--index", text, "--sub", std::to_string(sub), "--data", hex});
  EXPECT_EQ(r.exit_code, 0) << r.describe();
}

/// The EDS's default of INDEX/SUB as the one byte npm prints ("ff").
std::string eds_byte(uint16_t index, int sub) {
  const unsigned long v =
      std::stoul(eds_default(MB2CO_IONODE_EDS, index, static_cast<uint8_t>(sub)), nullptr, 0);
  char hex[4];
  std::snprintf(hex, sizeof hex, "%02lx", v);
  return hex;
}

/// TPDO1 frames on a raw socket of the test's own.
class Tpdo1Watch {
 public:
  Tpdo1Watch() { ok_ = can_.open("vcan0") && can_.accept_all(); }
  bool ok() const { return ok_; }
  void send_nmt_start() {
    CanFrame f{};
    f.id = 0x000;
    f.dlc = 2;
    f.data[0] = 0x01;
    f.data[1] = kNode;
    can_.send(f);
  }
  /// The next TPDO1's first byte (-1: none within the deadline).
  int next_input() {
    const auto deadline = std::chrono::steady_clock::now() + kPeerDeadline;
    for (;;) {
      linux_port::TimedCanFrame t;
      while (can_.receive(t))
        if (t.frame.id == kTpdo1 && !t.frame.extended() && t.frame.dlc >= 1) return t.frame.data[0];
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return -1;
      pollfd p{can_.fd(), POLLIN, 0};
      poll(&p, 1, static_cast<int>(left.count()));
    }
  }

 private:
  linux_port::SocketCanPort can_;
  bool ok_ = false;
};

/// Asks the board's panel and waits until npm reads `want` in 6000h/1 (the
/// image debounces the joystick 10 ms in its own time).
void panel(UnoProcess& board, const std::string& command, const char* want) {
  ASSERT_EQ(board.ask(command, "ok"), "ok");
  const auto deadline = std::chrono::steady_clock::now() + kPeerDeadline;
  while (npm_read(0x6000, 1) != want)
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << command << ": 6000h/1 never read " << want;
}

TEST(NpmClientVsIoNode, Cia401InputParameters) {
  Tpdo1Watch watch;
  ASSERT_TRUE(watch.ok());
  TempDir dir;
  UnoProcess board;
  ASSERT_TRUE(board.start_command(
      {uno_program(), "--image", "ionode", "--can", "vcan0", "--eeprom", dir.path("board.eeprom")},
      kPeerDeadline))
      << board.error();
  ASSERT_EQ(board.node_id(), kNode);

  // The image holds what the EDS says: CiA 401's defaults.
  for (const uint16_t index : {uint16_t{0x6002}, uint16_t{0x6006}, uint16_t{0x6007}, uint16_t{0x6008}}) {
    EXPECT_EQ(npm_read(index, 0), "02") << std::hex << index;
    for (int sub : {1, 2})
      EXPECT_EQ(npm_read(index, sub), eds_byte(index, sub)) << std::hex << index << "/" << sub;
  }
  EXPECT_EQ(npm_read(0x6005, 0), eds_byte(0x6005, 0));
  EXPECT_EQ(eds_byte(0x6005, 0), "01") << "global interrupt enable: TRUE";
  EXPECT_EQ(eds_byte(0x6006, 1), "ff") << "any change of any input";

  // Polarity: bit 0 inverted reads 1 with the joystick released.
  EXPECT_EQ(npm_read(0x6000, 1), "00");
  npm_write(0x6002, 1, "01");
  EXPECT_EQ(npm_read(0x6002, 1), "01");
  EXPECT_EQ(npm_read(0x6000, 1), "01");
  npm_write(0x6002, 1, "00");
  EXPECT_EQ(npm_read(0x6000, 1), "00");

  // Masks: UP (bit 0) only when it is pressed (low-to-high), nothing on any
  // change. The release sends nothing: the next TPDO1 is the next press.
  npm_write(0x6006, 1, "00");
  npm_write(0x6007, 1, "01");
  watch.send_nmt_start();
  EXPECT_EQ(watch.next_input(), 0x00) << "entering operational sends TPDO1";
  panel(board, "press UP", "01");
  EXPECT_EQ(watch.next_input(), 0x01) << "UP pressed: low-to-high is in 6007h";
  panel(board, "release UP", "00");
  panel(board, "press UP", "01");
  EXPECT_EQ(watch.next_input(), 0x01) << "the release (not in 6008h) sent no TPDO1";
  // Global interrupt off: the release and DOWN are not sent; on again, the
  // next rise is, with every input as it is.
  npm_write(0x6005, 0, "00");
  panel(board, "release UP", "00");
  panel(board, "press UP", "01");
  npm_write(0x6005, 0, "01");
  npm_write(0x6007, 1, "03");
  panel(board, "press DOWN", "03");
  EXPECT_EQ(watch.next_input(), 0x03) << "nothing sent while 6005h was FALSE";
  EXPECT_EQ(board.stop(), 0);
}

}  // namespace
}  // namespace test
}  // namespace mb2co

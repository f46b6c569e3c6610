// A 1010h save in the running line (issue 16 item 7): the simulated EEPROM
// takes 3.3 ms per byte (hil/sim/eeprom.h), the firmware writes one byte per
// pass when it is ready, and the station keeps its heartbeats and its Modbus
// answers meanwhile; the neighbour never loses it.
#include <gtest/gtest.h>

#include <vector>

#include "modbus/master_codec.h"
#include "sim/line.h"
#include "sim/pc_station.h"

namespace mb2co {
namespace sim {
namespace {

constexpr uint16_t kHrSave = 11;  // 1010h/1, two registers

/// Asks its station to save (FC 10h, HR 11-12 = "save"), then reads HR 11-12
/// once a cycle until they read 0 1: the poll docs/register-map.md describes.
class Saver : public PcProgram {
 public:
  explicit Saver(const Line& line) : line_(line) {}
  uint16_t first_request(uint8_t* out, uint16_t cap) override {
    if (done_ns != 0) return 0;
    if (answered_ns == 0) {
      static const uint16_t kSave[2] = {0x6576, 0x6173};
      asked_ns = line_.now();
      return modbus::build_write_registers(out, cap, 1, kHrSave, 2, kSave);
    }
    return modbus::build_read_request(out, cap, 1, modbus::fc::kReadHoldingRegisters, kHrSave, 2);
  }
  uint16_t on_response(const modbus::Response* r, uint8_t*, uint16_t) override {
    if (r == nullptr || r->exception != modbus::Exception::kNone) {
      ++failed;
      return 0;
    }
    if (answered_ns == 0) {
      answered_ns = line_.now();
    } else if (r->data_length == 4 && r->data[2] == 0 && r->data[3] == 1) {
      done_ns = line_.now();
    } else {
      ++busy_polls;
    }
    return 0;
  }
  SimNs asked_ns = 0;
  SimNs answered_ns = 0;
  SimNs done_ns = 0;
  int busy_polls = 0;
  int failed = 0;

 private:
  const Line& line_;
};

TEST(Save, AFirstSaveRunsOverPassesWhileTheLineKeepsItsHeartbeats) {
  LineConfig c;
  c.stations = 4;
  c.seed = 7;
  c.pc.cycle_ns = 20 * kNsPerMs;
  Line line(c, nullptr);
  Saver* saver = new Saver(line);
  line.pc(0).set_program(std::unique_ptr<PcProgram>(saver));
  std::vector<SimNs> beats_ns;  // station 0 = node 1: heartbeats 701h
  line.on_can = [&](const CanAttempt& a) {
    if (!a.error && a.frame.id == 0x701) beats_ns.push_back(a.end_ns);
  };
  int lost = 0;  // station 1 watches node 1 as its previous station
  line.on_state = [&](int station, const NodeState& before, const NodeState& after) {
    if (station == 1 && before.prev_status == 1 && after.prev_status != 1) ++lost;
  };
  line.power_on_all();
  line.run_until(kNsPerS);
  ASSERT_EQ(line.node(1).state().prev_status, 1) << "node 1 alive before the save";
  line.pc(0).start();
  line.run_until(6 * kNsPerS);

  ASSERT_NE(saver->answered_ns, 0u);
  ASSERT_NE(saver->done_ns, 0u) << "1010h/1 never read 1 again";
  EXPECT_EQ(saver->failed, 0) << "a request failed or got an exception";
  EXPECT_LT(saver->answered_ns - saver->asked_ns, 50 * kNsPerMs) << "answered at once";
  // The bench saved slot 0, so this save programs the erased slot 1 whole:
  // more than 440 bytes at 3.3 ms.
  const SimNs took_ns = saver->done_ns - saver->answered_ns;
  EXPECT_GT(took_ns, 440 * Eeprom::kByteNs);
  EXPECT_LT(took_ns, 2 * kNsPerS);
  EXPECT_GT(saver->busy_polls, 50) << "polled while the save ran";
  // Heartbeats (1017h = 100 ms) through the save within 10 %.
  int during = 0;
  for (size_t i = 1; i < beats_ns.size(); ++i) {
    if (beats_ns[i] < saver->asked_ns || beats_ns[i - 1] > saver->done_ns) continue;
    ++during;
    EXPECT_NEAR(static_cast<double>(beats_ns[i] - beats_ns[i - 1]), 100.0 * kNsPerMs, 10.0 * kNsPerMs)
        << "heartbeat " << i;
  }
  EXPECT_GE(during, 14) << "heartbeats seen during the save";
  EXPECT_EQ(lost, 0) << "station 2 lost node 1 during the save";
}

}  // namespace
}  // namespace sim
}  // namespace mb2co

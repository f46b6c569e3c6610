// Issue 22 item 8: a button held on the simulated board stays pressed for
// the image however often the image writes the button's port. simavr drives
// an input pin with its pull-up at every write of its PORT register, so the
// board must keep a pressed pin low as the switch to GND does on the Uno:
// START (D9 = PB1) shares port B with the MCP2515's chip select (D10 = PB2,
// written at every SPI instruction), STOP and STOP2 (PD3, PD4) share port D
// with the RUN-prev LED (PD6), the joystick (PC1-PC5) shares port C with
// RUN-next (A0 = PC0, gateway image).
//
// In process (UnoRig, no sockets), unpaced: each button of both images is
// held for 1 s of the image's time while its LEDs blink (gateway: both
// neighbours of a lone node 1 unknown; I/O node: RPDO1 toggling D7/D8) and
// SPI runs (heartbeats, PDOs, the RPDOs read from the chip). The image's own
// view is its input TPDO (6000h/1: gateway TPDO2 281h, I/O node TPDO1 1A0h),
// sent at every change of the debounced inputs: the button's bit must come
// set within the debounce and never go clear until the release.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "rig_frame.h"
#include "uno_rig.h"

namespace mb2co {
namespace uno {
namespace {

constexpr uint64_t kHoldUs = 1000000;
constexpr uint64_t kStepUs = 2000;
/// Debounce (gateway 2000h/6 = 20 ms, I/O node 2101h = 10 ms) plus loop passes.
constexpr uint64_t kSeenWithinUs = 60000;

struct ButtonCase {
  const char* image;  ///< --image NAME
  const char* elf;
  uint8_t button;      ///< index into the image's buttons = bit of 6000h/1
  uint32_t inputs_id;  ///< the TPDO that carries 6000h/1 (default node id)
  bool drive_leds;     ///< toggle the LEDs by RPDO1 (I/O node: 6200h/1)
};

std::string case_name(const ButtonCase& c) {
  return std::string(c.image) + "_" + find_image(c.image)->buttons.names[c.button];
}

class UnoButtonHeld : public ::testing::TestWithParam<ButtonCase> {};

TEST_P(UnoButtonHeld, StaysPressedForTheImageWhileLedsAndSpiWriteItsPort) {
  const ButtonCase& c = GetParam();
  const UnoImage& image = *find_image(c.image);
  const std::string name = image.buttons.names[c.button];
  const uint8_t bit = static_cast<uint8_t>(1u << c.button);
  auto rig = std::make_unique<UnoRig>(image);  // large: not on the stack
  const Status loaded = rig->load(c.elf);
  ASSERT_TRUE(loaded) << loaded.message();
  ASSERT_TRUE(rig->run_until_us(300000));
  ASSERT_NE(rig->booted_node(), 0) << "no boot-up";
  rig->can_in(rig_frame(0x000, {0x01, 0x00}));  // NMT start all (the gateway starts itself)
  ASSERT_TRUE(rig->run_until_us(rig->now_us() + 50000));
  rig->take_can_out();
  uint64_t ignored = 0;
  rig->take_led_change(&ignored);

  ASSERT_EQ(rig->panel().handle("press " + name, rig->now_us(), 0), "ok");
  rig->apply_buttons();
  const uint64_t pressed_us = rig->now_us();
  const uint64_t selects_before = rig->chip_selects();
  int led_changes = 0, inputs_frames = 0;
  uint64_t seen_us = 0;     // first input TPDO with the bit set
  uint64_t cleared_us = 0;  // first one after it with the bit clear (during the hold: the bug)
  bool led_level = false;
  uint64_t next_rpdo_us = pressed_us;
  while (rig->now_us() < pressed_us + kHoldUs) {
    if (c.drive_leds && rig->now_us() >= next_rpdo_us) {
      led_level = !led_level;
      rig->can_in(
          rig_frame(0x200 + rig->booted_node(), {static_cast<uint8_t>(led_level ? 0x03 : 0x00), 0x00}));
      next_rpdo_us += 100000;
    }
    ASSERT_TRUE(rig->run_until_us(rig->now_us() + kStepUs)) << rig->board().stop_reason();
    uint64_t changed_us = 0;
    if (rig->take_led_change(&changed_us)) ++led_changes;
    for (const CanWire::Sent& s : rig->take_can_out()) {
      if (s.frame.id != c.inputs_id || s.frame.dlc < 1) continue;
      ++inputs_frames;
      const uint64_t at_us = s.end_cycle / (UnoBoard::kCpuHz / 1000000u);
      if ((s.frame.data[0] & bit) != 0 && seen_us == 0) seen_us = at_us;
      if ((s.frame.data[0] & bit) == 0 && seen_us != 0 && cleared_us == 0) cleared_us = at_us;
    }
  }
  // The port really was written meanwhile: LEDs changed, the chip was talked to.
  EXPECT_GE(led_changes, 3) << "the LEDs did not blink during the hold";
  // The image talks to the MCP2515 at least once per loop pass (the I/O
  // node polls INT and reads each RPDO; the gateway also sends heartbeats).
  EXPECT_GE(rig->chip_selects() - selects_before, 20u) << "little SPI traffic during the hold";
  RecordProperty("chip_selects_during_hold", static_cast<int>(rig->chip_selects() - selects_before));
  RecordProperty("led_changes_during_hold", led_changes);
  ASSERT_NE(seen_us, 0u) << name << " held for 1 s never reached the image (" << inputs_frames
                         << " input frames)";
  EXPECT_LE(seen_us - pressed_us, kSeenWithinUs) << name << ": seen late";
  EXPECT_EQ(cleared_us, 0u) << name << " held for 1 s read released after "
                            << (cleared_us - pressed_us) / 1000 << " ms";

  // Released: the image sees that too, within the debounce.
  ASSERT_EQ(rig->panel().handle("release " + name, rig->now_us(), 0), "ok");
  rig->apply_buttons();
  const uint64_t released_us = rig->now_us();
  bool released_seen = false;
  while (!released_seen && rig->now_us() < released_us + kSeenWithinUs) {
    ASSERT_TRUE(rig->run_until_us(rig->now_us() + kStepUs));
    for (const CanWire::Sent& s : rig->take_can_out())
      if (s.frame.id == c.inputs_id && s.frame.dlc >= 1 && (s.frame.data[0] & bit) == 0) released_seen = true;
  }
  EXPECT_TRUE(released_seen) << name << ": the release did not reach the image";
}

const ButtonCase kCases[] = {
    {"gateway", MB2CO_UNO_GATEWAY_ELF, 0, 0x281, false},  // START, D9 = PB1 beside CS PB2
    {"gateway", MB2CO_UNO_GATEWAY_ELF, 1, 0x281, false},  // STOP, D3 = PD3
    {"gateway", MB2CO_UNO_GATEWAY_ELF, 2, 0x281, false},  // STOP2, D4 = PD4
    {"ionode", MB2CO_UNO_IONODE_ELF, 0, 0x1A0, true},     // UP, A1 = PC1
    {"ionode", MB2CO_UNO_IONODE_ELF, 1, 0x1A0, true},     // DOWN, A3
    {"ionode", MB2CO_UNO_IONODE_ELF, 2, 0x1A0, true},     // LEFT, A2
    {"ionode", MB2CO_UNO_IONODE_ELF, 3, 0x1A0, true},     // RIGHT, A5
    {"ionode", MB2CO_UNO_IONODE_ELF, 4, 0x1A0, true},     // CLICK, A4
};

INSTANTIATE_TEST_SUITE_P(EveryButton, UnoButtonHeld, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<ButtonCase>& p) { return case_name(p.param); });

}  // namespace
}  // namespace uno
}  // namespace mb2co

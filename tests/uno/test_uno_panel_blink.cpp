// A blinking LED is one state on the panel, as in mb2co-node ("prev=blink"):
// the gateway image blinks prev/next at 2 Hz while that neighbour is unknown,
// and mb2co-uno prints a leds line when what a LED shows changes, not at
// every 250 ms toggle. LEDs that never blink (the I/O node's D7/D8, driven by
// PDO) show every level, however quick.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "panel_channel.h"
#include "rig_frame.h"
#include "uno_rig.h"

namespace mb2co {
namespace uno {
namespace {

std::string levels(const PanelChannel& panel) {
  const std::string line = panel.leds_line(0);
  return line.substr(0, line.rfind(" at_us="));
}

TEST(UnoPanelBlink, ToggleWithinTheWindowIsABlinkUntilTheLedRests) {
  PanelChannel panel(gateway_image());  // LED 1 is prev
  panel.set_led(1, true, 1000000);
  EXPECT_EQ(levels(panel), "leds self=0 prev=1 next=0 lab=0 canerr=0") << "one change: a level";
  panel.set_led(1, false, 1250000);
  EXPECT_EQ(levels(panel), "leds self=0 prev=blink next=0 lab=0 canerr=0");
  panel.set_led(1, true, 1500000);
  EXPECT_FALSE(panel.settle_blinks(1500000 + PanelChannel::kBlinkWindowUs - 1));
  EXPECT_EQ(levels(panel), "leds self=0 prev=blink next=0 lab=0 canerr=0");
  EXPECT_TRUE(panel.settle_blinks(1500000 + PanelChannel::kBlinkWindowUs));
  EXPECT_EQ(levels(panel), "leds self=0 prev=1 next=0 lab=0 canerr=0") << "rests on: on";
}

TEST(UnoPanelBlink, LedsThatNeverBlinkShowEveryLevel) {
  PanelChannel gateway(gateway_image());  // LED 3 is lab (written by SDO)
  gateway.set_led(3, true, 1000000);
  gateway.set_led(3, false, 1100000);
  EXPECT_EQ(levels(gateway), "leds self=0 prev=0 next=0 lab=0 canerr=0");
  PanelChannel ionode(ionode_image());
  ionode.set_led(1, true, 1000000);
  ionode.set_led(1, false, 1050000);
  ionode.set_led(1, true, 1100000);
  EXPECT_EQ(levels(ionode), "leds d7=0 d8=1");
}

TEST(UnoPanelBlink, GatewayImageWithUnknownNeighboursPrintsTheBlinkOnce) {
  static UnoRig rig(gateway_image());  // large, as in mb2co-uno
  const Status loaded = rig.load(MB2CO_UNO_GATEWAY_ELF);
  ASSERT_TRUE(loaded) << loaded.message();
  // What mb2co-uno prints: a line whenever the levels text changes.
  std::vector<std::string> printed;
  auto run_for_ms = [&](uint32_t ms, bool next_alive) {
    for (uint32_t t = 0; t < ms; t += 10) {
      if (next_alive && t % 100 == 0) {  // node 2 (next in the default ring): heartbeat and TPDO1
        rig.can_in(rig_frame(0x702, {0x05}));
        rig.can_in(rig_frame(0x182, {0x00, 0x00, 0x00}));
      }
      ASSERT_TRUE(rig.run_until_us(rig.now_us() + 10000));
      uint64_t at = 0;
      rig.take_led_change(&at);
      rig.panel().settle_blinks(rig.now_us());
      if (printed.empty() || levels(rig.panel()) != printed.back()) printed.push_back(levels(rig.panel()));
    }
  };
  run_for_ms(4000, false);  // 16 toggles of each neighbour LED
  ASSERT_FALSE(printed.empty());
  EXPECT_NE(printed.back().find(" prev=blink next=blink "), std::string::npos) << printed.back();
  EXPECT_LE(printed.size(), 6u) << "a line per state, not per toggle; last: " << printed.back();

  const size_t before = printed.size();
  run_for_ms(2000, true);
  EXPECT_NE(printed.back().find(" prev=blink next="), std::string::npos) << printed.back();
  EXPECT_EQ(printed.back().find(" next=blink "), std::string::npos)
      << "next is known now: " << printed.back();
  EXPECT_LE(printed.size() - before, 3u) << printed.back();
}

}  // namespace
}  // namespace uno
}  // namespace mb2co

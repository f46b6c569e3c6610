// The I/O node image (mb2co-ionode.elf) on the simulated board, in process
// (no CAN socket): the rig's --image ionode wiring against the real image.
// The joystick names drive the pins the image reads (UP is A1, bit 0 of
// 6000h/1, out in TPDO1), and the LEDs D7/D8 the image drives from 6200h/1
// (RPDO1) are the panel's d7/d8. The panel's parser for both images.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rig_frame.h"
#include "uno_rig.h"

namespace mb2co {
namespace uno {
namespace {

/// The frames the image sent with `id`, oldest first.
std::vector<CanFrame> sent_on(UnoRig& rig, uint32_t id) {
  std::vector<CanFrame> out;
  for (const CanWire::Sent& s : rig.take_can_out()) {
    if (s.frame.id == id) out.push_back(s.frame);
  }
  return out;
}

TEST(UnoIoNode, JoystickPinsAreTheInputsAndLedPinsTheOutputsOfTheImage) {
  static UnoRig rig(ionode_image());  // large, as in mb2co-uno
  const Status loaded = rig.load(MB2CO_UNO_IONODE_ELF);
  ASSERT_TRUE(loaded) << loaded.message();
  ASSERT_TRUE(rig.run_until_us(200000));
  ASSERT_EQ(rig.booted_node(), 0x20) << "a blank EEPROM: the default id";
  rig.can_in(rig_frame(0x000, {0x01, 0x20}));  // NMT start
  ASSERT_TRUE(rig.run_until_us(rig.now_us() + 20000));
  rig.take_can_out();

  EXPECT_EQ(rig.panel().handle("press up", rig.now_us(), 0), "ok");
  rig.apply_buttons();
  ASSERT_TRUE(rig.run_until_us(rig.now_us() + 50000));  // debounce 2101h = 10 ms
  std::vector<CanFrame> tpdo = sent_on(rig, 0x1A0);
  ASSERT_EQ(tpdo.size(), 1u) << "TPDO1 on the change";
  EXPECT_EQ(tpdo[0].dlc, 2);
  EXPECT_EQ(tpdo[0].data[0], 0x01) << "UP is bit 0 of 6000h/1";

  EXPECT_EQ(rig.panel().handle("press RIGHT", rig.now_us(), 0), "ok");
  rig.apply_buttons();
  ASSERT_TRUE(rig.run_until_us(rig.now_us() + 50000));
  tpdo = sent_on(rig, 0x1A0);
  ASSERT_EQ(tpdo.size(), 1u);
  EXPECT_EQ(tpdo[0].data[0], 0x09) << "RIGHT is bit 3";

  rig.can_in(rig_frame(0x220, {0x02, 0x00}));  // RPDO1: 6200h/1 bit 1 = D8
  ASSERT_TRUE(rig.run_until_us(rig.now_us() + 20000));
  uint64_t changed_us = 0;
  EXPECT_TRUE(rig.take_led_change(&changed_us));
  EXPECT_EQ(rig.panel().leds_line(7), "leds d7=0 d8=1 at_us=7");
  rig.can_in(rig_frame(0x220, {0x01, 0x00}));
  ASSERT_TRUE(rig.run_until_us(rig.now_us() + 20000));
  EXPECT_EQ(rig.panel().leds_line(7), "leds d7=1 d8=0 at_us=7");
}

TEST(UnoPanel, EachImageHasItsOwnButtonNames) {
  PanelChannel ionode(ionode_image());
  EXPECT_EQ(ionode.handle("press START", 0, 0),
            "error unknown button 'START' (UP, DOWN, LEFT, RIGHT, CLICK)");
  EXPECT_EQ(ionode.handle("click click 50", 0, 0), "ok");
  EXPECT_EQ(ionode.buttons(), 0x10) << "CLICK is the fifth";
  ionode.process(49999);
  EXPECT_EQ(ionode.buttons(), 0x10);
  ionode.process(50000);
  EXPECT_EQ(ionode.buttons(), 0);
  EXPECT_EQ(ionode.handle("leds?", 0, 5), "leds d7=0 d8=0 at_us=5");
  EXPECT_EQ(ionode.handle("state?", 0, 0).rfind("error unknown command", 0), 0u);

  PanelChannel gateway;
  EXPECT_EQ(gateway.handle("press UP", 0, 0), "error unknown button 'UP' (START, STOP, STOP2)");
  EXPECT_EQ(gateway.handle("press stop2", 0, 0), "ok");
  EXPECT_EQ(gateway.buttons(), 0x04);
  EXPECT_EQ(gateway.handle("leds?", 0, 5), "leds self=0 prev=0 next=0 lab=0 canerr=0 at_us=5");
}

TEST(UnoImages, NamesFilesAndUnknownNames) {
  EXPECT_EQ(image_names(), "gateway, network, ionode, echo");
  ASSERT_NE(find_image("ionode"), nullptr);
  EXPECT_STREQ(find_image("ionode")->elf, "mb2co-ionode.elf");
  EXPECT_STREQ(find_image("gateway")->elf, "mb2co-gateway.elf");
  // The network gateway: its own file on the station's pins.
  ASSERT_NE(find_image("network"), nullptr);
  EXPECT_STREQ(find_image("network")->elf, "mb2co-gateway-network.elf");
  EXPECT_EQ(find_image("network")->button_pins, gateway_image().button_pins);
  EXPECT_EQ(find_image("network")->led_pins, gateway_image().led_pins);
  EXPECT_TRUE(find_image("network")->gateway);
  EXPECT_EQ(find_image("bridge"), nullptr);
}

}  // namespace
}  // namespace uno
}  // namespace mb2co

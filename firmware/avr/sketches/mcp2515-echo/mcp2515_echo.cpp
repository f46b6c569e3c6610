// mcp2515-echo: the MCP2515 at 500 kbit/s answers every frame it receives
// with the same frame, id + 1 (wrapping inside 11 or 29 bits). A bring-up
// check for the shield, the driver and the bus: `cansend can0 123#11` on a PC
// adapter must come back as 124#11. Serial (115200) reports init and errors;
// the shield LED D7 toggles per echoed frame, D8 lights while not error-active.
#include <Arduino.h>

#include "mcp2515.h"
#include "pins.h"
#include "port/mcp2515_spi.h"

namespace {

using mb2co::CanFrame;
namespace can = mb2co::mcp2515;

can::Driver driver(mb2co::avr::mcp2515_spi());

/// service() also runs this often without INT: bus-off recovery raises none.
constexpr unsigned long kServicePeriodMs = 10;
unsigned long last_service_ms = 0;
bool led_toggle = false;

void report(uint8_t events) {
  if (events & can::kEventRxOverflow) Serial.println(F("rx overflow"));
  if (events & can::kEventBusOff) Serial.println(F("bus-off"));
  if (events & can::kEventBusOffRecovered) Serial.println(F("bus-off recovered"));
  if (events & can::kEventStateChanged) {
    Serial.print(F("error state "));
    Serial.println(static_cast<uint8_t>(driver.error_state()));
  }
}

}  // namespace

void setup() {
  Serial.begin(115200);
  pinMode(mb2co::pins::kCanInt, INPUT);  // the MCP2515 drives INT push-pull
  pinMode(mb2co::pins::kShieldLed1, OUTPUT);
  pinMode(mb2co::pins::kShieldLed2, OUTPUT);
  mb2co::avr::mcp2515_spi_begin();
  while (!driver.begin(can::Bitrate::k500k, can::Mode::kNormal)) {
    Serial.println(F("mcp2515: no answer, retrying"));
    digitalWrite(mb2co::pins::kShieldLed2, HIGH);
    delay(1000);
  }
  digitalWrite(mb2co::pins::kShieldLed2, LOW);
  Serial.println(F("mcp2515-echo: 500 kbit/s, echoing id+1"));
}

void loop() {
  const unsigned long now_ms = millis();
  if (digitalRead(mb2co::pins::kCanInt) == LOW || now_ms - last_service_ms >= kServicePeriodMs) {
    last_service_ms = now_ms;
    const uint8_t events = driver.service();
    if (events != 0) {
      report(events);
      digitalWrite(mb2co::pins::kShieldLed2, driver.error_state() == can::ErrorState::kActive ? LOW : HIGH);
    }
  }
  CanFrame frame;
  while (driver.receive(frame)) {
    frame.id = (frame.id + 1) & (frame.extended() ? 0x1FFFFFFFul : 0x7FFul);
    driver.send(frame);  // all three buffers busy: dropped, counted in tx_full
    led_toggle = !led_toggle;
    digitalWrite(mb2co::pins::kShieldLed1, led_toggle ? HIGH : LOW);
  }
}

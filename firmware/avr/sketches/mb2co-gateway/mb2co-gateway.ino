// mb2co-gateway: the full station firmware for the Arduino Uno + SparkFun CAN-BUS shield.
// The code is in gateway_main.cpp (setup() and loop()), the same file CMake
// builds (firmware/avr/sketches/mb2co-gateway/CMakeLists.txt). This file exists so the
// folder opens in the Arduino IDE; the include below makes the IDE find the
// mb2co library (firmware/avr/arduino/install-library.sh, see
// firmware/avr/README.md).
#include <mb2co.h>

// mb2co-ionode: the CiA 401 I/O node for the Arduino Uno + SparkFun CAN-BUS shield.
// The code is in ionode_main.cpp (setup() and loop()), the same file CMake
// builds (firmware/avr/sketches/mb2co-ionode/CMakeLists.txt). This file exists so the
// folder opens in the Arduino IDE; the include below makes the IDE find the
// mb2co_ionode library, the mb2co sources with the ionode profile
// (firmware/avr/arduino/install-library.sh, see
// firmware/avr/README.md).
#include <mb2co_ionode.h>

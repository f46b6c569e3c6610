// Root header of the "mb2co" Arduino library (firmware/avr/arduino): a sketch
// that includes it makes the Arduino IDE find the library, whose src/ folder
// then is an include directory ("canopen/node.h", "port/uart.h", "pins.h").
// CMake builds do not need it; it only brings in the pin map.
#pragma once
#include "pins.h"

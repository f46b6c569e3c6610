// mb2co-gateway-network: the station firmware plus Modbus FC 2Bh / MEI 0Dh
// (the PC's Modbus master reaches every node of the CAN network), for the
// Arduino Uno + SparkFun CAN-BUS shield. The code is gateway_main.cpp
// (setup() and loop(), the station's), the same file CMake builds
// (firmware/avr/sketches/mb2co-gateway-network/CMakeLists.txt); what differs
// is the profile, which the library's header brings: <mb2co_network.h> is the
// mb2co library made with profile "network" (firmware/avr/arduino/
// install-library.sh, see firmware/avr/README.md). Which image to flash for
// what: docs/gateway-network.md.
#include <mb2co_network.h>

// The virtual multi-drop serial line and the real I/O node on it, for the
// serialnet tests: the simulator's own (hil/sim/serial_bus.h,
// hil/sim/serial_station.h), under the names these tests use.
#pragma once
#include "sim/serial_bus.h"
#include "sim/serial_station.h"

namespace mb2co {
namespace test {

using sim::BusDevice;
using sim::SerialBus;
using Station = sim::SerialStation;

}  // namespace test
}  // namespace mb2co

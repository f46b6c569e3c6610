// StationSafety (station_safety_tests.h) on mb2co-node: the gateway firmware
// built for Linux, its EEPROM a file.
#include "station_safety_tests.h"

namespace mb2co {
namespace test {

INSTANTIATE_TYPED_TEST_SUITE_P(Node, StationSafety, NodeProcess);

}  // namespace test
}  // namespace mb2co

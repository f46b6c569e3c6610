// StationSafety (tests/node/station_safety_tests.h) on the real Uno image in
// mb2co-uno: the same requests, the same answers as mb2co-node.
#include "station_safety_tests.h"
#include "uno_harness.h"

namespace mb2co {
namespace test {

INSTANTIATE_TYPED_TEST_SUITE_P(Uno, StationSafety, UnoProcess);

}  // namespace test
}  // namespace mb2co

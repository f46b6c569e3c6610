// Issue 16 item 6 on mb2co-node (tests/support/storage_damage_tests.h): every
// kind of damaged --eeprom file starts the node with the defaults or the
// older set, reported by one warning line on stderr, the counter 2003h and
// 1001h bit 0 over Modbus; a blank file reports nothing; the file stays as it
// was. A path the node could never save to is refused at start
// (test_node_cli.cpp: Eeprom.AnUnusablePathExits1WithOneLine).
#include "storage_damage_tests.h"

namespace mb2co {
namespace test {
namespace {

class NodeEepromFile : public StorageDamage<NodeProcess, true, 0> {};

TEST_F(NodeEepromFile, TheGoodFileHoldsTwoSetsAndStartsWithTheNewerQuietly) {
  good_file_starts_quietly();
}

TEST_P(NodeEepromFile, StartsSafelyReportsItAndKeepsTheFile) {
  damaged_file_starts_safely_and_is_reported();
}

INSTANTIATE_TEST_SUITE_P(Kinds, NodeEepromFile, ::testing::Range<size_t>(0, storage_damage::kinds().size()),
                         storage_kind_test_name);

}  // namespace
}  // namespace test
}  // namespace mb2co

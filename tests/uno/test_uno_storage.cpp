// Issue 16 item 6 on the real Uno image in mb2co-uno, whose --eeprom file is
// the Uno's 1 KiB EEPROM (tests/support/storage_damage_tests.h): every kind of
// damaged EEPROM starts the station with the defaults or the older set,
// reported by the counter 2003h and 1001h bit 0 over Modbus (EMCY 5530h after
// the boot-up: the same core, gateway.StorageReport); an erased EEPROM
// reports nothing; the EEPROM is never written by a start.
#include "storage_damage_tests.h"
#include "uno_harness.h"

namespace mb2co {
namespace test {
namespace {

class UnoEeprom : public StorageDamage<UnoProcess, false, 1024> {};

TEST_F(UnoEeprom, TheGoodImageHoldsTwoSetsAndStartsWithTheNewerQuietly) {
  good_file_starts_quietly();
}

TEST_P(UnoEeprom, StartsSafelyReportsItAndKeepsTheImage) {
  damaged_file_starts_safely_and_is_reported();
}

INSTANTIATE_TEST_SUITE_P(Kinds, UnoEeprom, ::testing::Range<size_t>(0, storage_damage::kinds().size()),
                         storage_kind_test_name);

}  // namespace
}  // namespace test
}  // namespace mb2co

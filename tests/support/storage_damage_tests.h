// Issue 16 item 6, black box, shared by mb2co-node (tests/node) and the real
// Uno image in mb2co-uno (tests/uno): every kind of damaged EEPROM file
// (storage_damage.h) starts the station with the defaults or the older set;
// the damage is reported by the counter 2003h (IR 23) and 1001h bit 0
// (IR 19) over Modbus, and by mb2co-node also as one warning line on stderr
// (EMCY 5530h: gateway.StorageReport, in-process); a blank file reports
// nothing; the file is left as it was (a start never loses a valid set).
// The program runs with --can none on a pty; libmodbus is its master.
#pragma once
#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "node_harness.h"
#include "storage_damage.h"

namespace mb2co {
namespace test {

inline std::vector<uint8_t> read_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

inline void write_file(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// A kind's name as a test name: "all FF (erased)" -> "AllFFErased".
inline std::string storage_kind_test_name(const ::testing::TestParamInfo<size_t>& info) {
  std::string name;
  bool upper = true;
  for (const char* p = storage_damage::kinds()[info.param].name; *p != '\0'; ++p) {
    const unsigned char c = static_cast<unsigned char>(*p);
    if (!std::isalnum(c)) {
      upper = true;
      continue;
    }
    name += upper ? static_cast<char>(std::toupper(c)) : static_cast<char>(c);
    upper = false;
  }
  return name;
}

/// Process: NodeProcess or UnoProcess. `kWarns`: the station has a stderr
/// (mb2co-node) and warns there; the Uno has none (mb2co-uno's own stderr
/// line is the simulator's, not checked). `kImageBytes`: 0, or the only file size
/// the program takes (mb2co-uno: the Uno's 1 KiB; a cut file is then one
/// whose tail is erased, FFh).
template <class Process, bool kWarns, size_t kImageBytes>
class StorageDamage : public ::testing::TestWithParam<size_t> {
 protected:
  static constexpr int kHrNodeId = 2, kHrDebounce = 7, kHrSave = 11;
  static constexpr int kIrErrorRegister = 19, kIrStorageDamage = 23;
  /// The Uno's first save programs ~450 EEPROM bytes at 3.3 ms each.
  static constexpr std::chrono::milliseconds kSaveTimeout = 3000ms;

  static std::vector<std::string> args_for(const TempDir& dir) {
    return {"--can", "none", "--pty", dir.path("station.pty"), "--eeprom", dir.path("eeprom")};
  }

  /// The good file, made over Modbus: set A (node id 9) saved, then set B
  /// (node id 12), both with the marker debounce. Made once per process.
  static const std::vector<uint8_t>& good_file() {
    static const std::vector<uint8_t> bytes = [] {
      TempDir dir;
      Process p;
      if (!p.start(args_for(dir))) return std::vector<uint8_t>();
      ModbusMaster m;
      if (!m.open(p.device(), kSaveTimeout)) return std::vector<uint8_t>();
      // "save" is answered at once and runs over passes: done when HR 11-12
      // read 0 1 again (docs/register-map.md); a save meanwhile is busy (06).
      auto save = [&m] {
        const uint16_t signature[2] = {0x6576, 0x6173};  // "save", high word first
        return modbus_write_registers(m.ctx(), kHrSave, 2, signature) == 2 && m.wait_saved(kSaveTimeout);
      };
      bool ok = modbus_write_register(m.ctx(), kHrDebounce, storage_damage::kMarker) == 1 &&
                modbus_write_register(m.ctx(), kHrNodeId, 9) == 1 && save() &&
                modbus_write_register(m.ctx(), kHrNodeId, 12) == 1 && save();
      m.close();
      ok = p.stop() == 0 && ok;
      return ok ? read_file(dir.path("eeprom")) : std::vector<uint8_t>();
    }();
    return bytes;
  }

  /// What one start with `image` shows over Modbus.
  struct Seen {
    int node_id = -1, debounce = -1, damage_count = -1, error_bit = -1;
    std::string err;
  };
  static void start_with(const TempDir& dir, const std::vector<uint8_t>& image, Seen* seen) {
    write_file(dir.path("eeprom"), image);
    Process p;
    ASSERT_TRUE(p.start(args_for(dir))) << p.error();
    seen->node_id = p.node_id();
    ModbusMaster m;
    ASSERT_TRUE(m.open(p.device(), kSaveTimeout)) << m.error();
    seen->debounce = m.holding_register(kHrDebounce);
    seen->damage_count = m.input_register(kIrStorageDamage);
    seen->error_bit = m.input_register(kIrErrorRegister) & 1;
    m.close();
    EXPECT_EQ(p.stop(), 0);
    seen->err = p.child.stderr_text();
  }

  void good_file_starts_quietly() {
    const std::vector<uint8_t>& image = good_file();
    ASSERT_GT(image.size(), storage_damage::kSlot + storage_damage::kHeader) << "two saves fill both slots";
    TempDir dir;
    Seen seen;
    start_with(dir, image, &seen);
    EXPECT_EQ(seen.node_id, 12) << "the newer set";
    EXPECT_EQ(seen.damage_count, 0);
    EXPECT_EQ(seen.error_bit, 0);
    if (kWarns) {
      EXPECT_EQ(seen.err, "");
    }
  }

  void damaged_file_starts_safely_and_is_reported() {
    namespace sd = storage_damage;
    const sd::Kind& kind = sd::kinds()[GetParam()];
    SCOPED_TRACE(kind.name);
    std::vector<uint8_t> image = good_file();
    ASSERT_FALSE(image.empty()) << "the good file could not be made";
    ASSERT_TRUE(kind.apply(image));
    if (kImageBytes != 0) image.resize(kImageBytes, 0xFF);
    const bool older = kind.verdict == sd::Verdict::kOlderSet;
    const bool reported = kind.verdict != sd::Verdict::kNoSet;
    TempDir dir;
    Seen seen;
    start_with(dir, image, &seen);
    EXPECT_EQ(seen.node_id, older ? 9 : 1) << "the older set, or the defaults";
    EXPECT_EQ(seen.debounce, older ? sd::kMarker : 20) << "a damaged set is refused whole";
    EXPECT_EQ(seen.damage_count, reported ? 1 : 0);
    EXPECT_EQ(seen.error_bit, reported ? 1 : 0);
    if (kWarns && reported) {
      EXPECT_EQ(seen.err.rfind("mb2co-node: warning: " + dir.path("eeprom") + ": ", 0), 0u) << seen.err;
      EXPECT_EQ(seen.err.find('\n'), seen.err.size() - 1) << "one line: " << seen.err;
      EXPECT_NE(seen.err.find(older ? "older" : "defaults"), std::string::npos) << seen.err;
    } else if (kWarns) {
      EXPECT_EQ(seen.err, "") << "a blank file is no damage";
    }
    EXPECT_EQ(read_file(dir.path("eeprom")), image) << "a start changed the file";
  }
};

}  // namespace test
}  // namespace mb2co

// libFuzzer target: mb2co-timing's CSV reader (pcapp/timing/csv_set) on any
// bytes. Invariants (violations abort): an accepted set has at least one
// message, unique names that are non-empty UTF-8 without control characters
// below 20h or NUL, ids within 11/29 bits, periods and deadlines above 0,
// and its JSON rendering of every name (report.h json_string) is a string
// without raw control characters; a refused one has a one-line error naming
// the source.
#include <stdint.h>
#include <string.h>

#include <set>
#include <string>
#include <vector>

#include "csv_set.h"
#include "fuzz_support.h"
#include "report.h"

using namespace mb2co;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<timing::MessageSpec> set;
  const Status status = timing_cli::parse_message_csv(text, "fuzz.csv", set);
  const std::string& error = status.message();
  if (!status) {
    fuzz::require(error.rfind("fuzz.csv:", 0) == 0, "an error that does not name the source");
    fuzz::require(error.find('\n') == std::string::npos, "an error of more than one line");
    return 0;
  }
  fuzz::require(!set.empty(), "an accepted set without messages");
  std::set<std::string> names;
  for (const timing::MessageSpec& m : set) {
    const size_t n = strnlen(m.name, timing::kNameCapacity);
    fuzz::require(n > 0 && n < timing::kNameCapacity, "an empty or unterminated name");
    const std::string name(m.name, n);
    fuzz::require(names.insert(name).second, "a name used twice");
    fuzz::require(m.id <= (m.extended ? 0x1FFFFFFFu : 0x7FFu), "an id beyond its format");
    fuzz::require(m.period_us > 0 && m.deadline_us > 0 && m.dlc <= 8,
                  "a period, deadline or DLC out of range");
    for (const char c : timing_cli::json_string(name)) {
      fuzz::require(static_cast<unsigned char>(c) >= 0x20, "a raw control character in JSON");
    }
  }
  return 0;
}

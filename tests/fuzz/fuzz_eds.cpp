// libFuzzer target: the CiA 306 EDS/DCF reader and writer (pcapp/eds) on any
// bytes. Invariants (violations abort): the reader never crashes or throws;
// a refused file gets one line "fuzz.eds:LINE: what" with LINE within the
// file; an accepted file written as a DCF (and as an EDS) reads back as the
// same model; read for a node id, every $NODEID value is what resolve()
// makes of the symbolic one.
#include <stdint.h>

#include <algorithm>
#include <string>

#include "eds_reader.h"
#include "eds_value.h"
#include "eds_writer.h"
#include "fuzz_support.h"

using namespace mb2co;

namespace {

void same_resolved(const std::optional<eds::Value>& symbolic, const std::optional<eds::Value>& evaluated,
                   eds::DataType type, uint8_t node_id) {
  fuzz::require(symbolic.has_value() == evaluated.has_value(), "a value present for one reading only");
  if (!symbolic) return;
  const std::optional<eds::Value> resolved = eds::resolve(type, *symbolic, node_id);
  fuzz::require(resolved.has_value() && *resolved == *evaluated,
                "a $NODEID value evaluated unlike resolve()");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const eds::ParseResult r = eds::parse(text, "fuzz.eds");
  if (!r) {
    const std::string error = r.error.text();
    fuzz::require(error.rfind("fuzz.eds:", 0) == 0, "an error that does not name the file");
    fuzz::require(error.find('\n') == std::string::npos, "an error of more than one line");
    const long lines = static_cast<long>(std::count(text.begin(), text.end(), '\n')) + 1;
    fuzz::require(r.error.line >= 1 && r.error.line <= lines, "an error line outside the file");
    return 0;
  }
  const eds::DeviceDescription& m = *r.model;
  const uint8_t node_id = static_cast<uint8_t>(1 + size % 127);
  const eds::ParseResult dcf = eds::parse(eds::write_dcf(m, node_id), "fuzz.dcf");
  fuzz::require(static_cast<bool>(dcf), "a written DCF that does not read back");
  fuzz::require(*dcf.model == eds::with_commissioning(m, node_id), "a DCF that reads back as another model");
  const eds::ParseResult again = eds::parse(eds::write_eds(m), "fuzz.eds");
  fuzz::require(static_cast<bool>(again) && *again.model == m, "an EDS that reads back as another model");

  const eds::ParseResult for_node = eds::parse(text, "fuzz.eds", node_id);
  if (for_node) {  // limits may refuse an evaluated value they could not check symbolically
    for (const auto& o : m.objects) {
      const eds::Object* other = for_node.model->find(o.first);
      fuzz::require(other != nullptr && other->subs.size() == o.second.subs.size(),
                    "objects differ by node id");
      for (size_t k = 0; k < o.second.subs.size(); ++k) {
        const eds::SubObject& a = o.second.subs[k];
        const eds::SubObject& b = other->subs[k];
        same_resolved(a.default_value, b.default_value, a.type, node_id);
        same_resolved(a.parameter_value, b.parameter_value, a.type, node_id);
      }
    }
  }
  return 0;
}

// The FC 2Bh / MEI 0Dh request parser (shared/modbus/network_pdu) on any
// bytes after "2B 0D": the slave routes only FC 2Bh with MEI 0Dh to the
// parser, which therefore does not check them again (issue 23's network
// image), so a PDU with another header is not the parser's input. A
// request it accepts must be canonical: the master-side builder writes the
// very same PDU back from what was parsed, every field is in its documented
// range, the data lie inside the request; and the response builders never
// write beyond the capacity they are given.
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "fuzz_support.h"
#include "modbus/network_pdu.h"

using namespace mb2co;
using namespace mb2co::modbus;

namespace {

void check_accepted(const uint8_t* pdu, uint16_t length, const NetMessage& m) {
  fuzz::require(m.node_id <= 127u, "node id above 127");
  if (m.service == NetService::kSdoUpload || m.service == NetService::kSdoDownload)
    fuzz::require(m.node_id >= 1u, "SDO to node 0");
  if (m.data_length != 0u)
    fuzz::require(m.data >= pdu && m.data + m.data_length <= pdu + length, "data outside the request");
  if (m.service == NetService::kSdoDownload) {
    fuzz::require(m.count == m.data_length, "download count != data");
    fuzz::require(static_cast<uint32_t>(m.start) + m.count <= m.object_size, "part beyond its object");
  }
  fuzz::require(!m.more_follows || m.service == NetService::kSdoDownload,
                "more follows on a one-part service");
  // Canonical: built again from the fields, the same bytes.
  uint8_t again[kMaxAduBytes];
  const uint16_t n = build_net_request(again, sizeof again, 1, m);
  fuzz::require(n == length + 3u, "rebuilt request has another length");
  fuzz::require(memcmp(again + 1, pdu, length) == 0, "rebuilt request differs");
  // The response in a buffer of every size up to what it needs: it fits
  // exactly or is refused (ASan sees any write beyond).
  NetMessage r = m;
  r.data = nullptr;
  r.data_length = 0;
  if (m.service == NetService::kNmt) {
    r.data = m.data;
    r.data_length = 1;
  }
  for (uint16_t cap = 0; cap <= 20u; ++cap) {
    uint8_t* out = new uint8_t[cap == 0u ? 1u : cap];
    const uint16_t len = build_net_response(out, cap, r);
    fuzz::require(len <= cap, "response longer than its room");
    delete[] out;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > net::kMaxPduBytes - 2u) return 0;
  uint8_t pdu[net::kMaxPduBytes];
  pdu[0] = fc::kEncapsulatedInterface;
  pdu[1] = kMeiCanopenReference;
  if (size != 0u) memcpy(pdu + 2, data, size);
  NetMessage m{};
  const uint16_t length = static_cast<uint16_t>(size + 2u);
  if (parse_net_request(pdu, length, m)) check_accepted(pdu, length, m);
  return 0;
}

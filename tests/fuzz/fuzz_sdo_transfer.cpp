// libFuzzer target: both ends of an SDO transfer with block transfer and a
// domain object compiled in (MB2CO_CONFIG_SDO_BLOCK, the host build of mb2co-node
// and mb2co-master), each facing a peer that says anything.
//
// Input: byte 0 picks the side and the request (client: upload/download,
// expedited-segmented-block, size; server: which object), then 9-byte
// records: a time step (ms) and the 8 bytes of a frame from the peer.
//
// Invariants (a violation aborts with a message):
//  * client: every frame it sends is 8 bytes on 600h+id; an upload never
//    writes more than its capacity nor outside [0, capacity); once virtual
//    time passes its timeout after the last input it is no longer busy (no
//    hang); a download reads only inside the data it was given.
//  * server: every answer is 8 bytes on 580h+id; the domain's content
//    changes only by a commit of a completed download, and then has exactly
//    the size that download announced (when it announced one); the server is
//    idle once its timeout passed.
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vector>

#include "canopen/sdo_client.h"
#include "canopen/sdo_domain.h"
#include "canopen/sdo_server.h"
#include "ionode/io_node.h"

using namespace mb2co;

namespace {

const uint8_t kNode = 5;

void fail(const char* what) {
  fprintf(stderr, "invariant violated: %s\n", what);
  abort();
}

bool check_sent(void* ctx, const CanFrame& f) {
  const uint32_t want = *static_cast<uint32_t*>(ctx);
  if (f.id != want || f.dlc != 8 || f.flags != 0) fail("a frame that is not 8 bytes on the SDO COB-ID");
  return true;
}

struct Upload {
  std::vector<uint8_t> got;
  uint32_t capacity;
};
canopen::SdoAbort upload_write(void* ctx, uint32_t offset, const uint8_t*, uint16_t n) {
  Upload& u = *static_cast<Upload*>(ctx);
  if (offset != u.got.size()) fail("upload offsets not in order");
  if (static_cast<uint64_t>(offset) + n > u.capacity) fail("upload beyond its capacity");
  u.got.resize(offset + n);
  return canopen::kSdoOk;
}
struct Download {
  uint32_t size;
};
canopen::SdoAbort download_read(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n) {
  if (static_cast<uint64_t>(offset) + n > static_cast<Download*>(ctx)->size)
    fail("download read past its data");
  memset(buf, 0xA5, n);
  return canopen::kSdoOk;
}

void fuzz_client(const uint8_t* data, size_t size) {
  const uint8_t op = data[0];
  canopen::SdoClient client{};
  client.init(kNode);
  client.set_timeout_us(50000);
  uint32_t out_id = 0x600 + kNode;
  const CanSink sink{&check_sent, &out_id};
  uint32_t now = 1000;
  Upload up;
  up.capacity = 1u + (op >> 4) * 97u;  // 1..1456 bytes
  Download down{(op >> 4) * 131u};     // 0..1965 bytes
  const canopen::SdoMode mode = static_cast<canopen::SdoMode>((op >> 1) % 3);
  if (op & 1) {
    client.start_download(0x2000, 1, mode, canopen::SdoData{nullptr, &download_read, &down}, down.size, now,
                          sink);
  } else {
    client.start_upload(0x2000, 1, mode, canopen::SdoData{&upload_write, nullptr, &up}, up.capacity, now,
                        sink);
  }
  for (size_t i = 1; i + 9 <= size; i += 9) {
    now += data[i] * 1000u;
    CanFrame f{};
    f.id = 0x580 + kNode;
    f.dlc = 8;
    memcpy(f.data, data + i + 1, 8);
    client.process(now, sink);
    client.on_frame(f, now, sink);
  }
  // Time passes with no answer: the client must give up.
  for (int k = 0; k < 200 && client.busy(); ++k) {
    now += 10000;
    client.process(now, sink);
  }
  if (client.busy()) fail("client still busy long after its timeout");
  if (client.status() == canopen::SdoClient::kDone && !(op & 1) && client.size_known() &&
      client.size() != up.got.size())
    fail("upload done with another size than announced");
}

/// 1F50h/1 in RAM, staged downloads, as mb2co-node's program data.
struct Domain {
  std::vector<uint8_t> content = std::vector<uint8_t>(300, 7);
  std::vector<uint8_t> staging;
  uint32_t announced = 0;
  bool indicated = false;
  int commits = 0;
};
bool owns(void*, uint16_t index, uint8_t sub) {
  return index == 0x1F50 && sub == 1;
}
uint32_t dsize(void* ctx, uint16_t, uint8_t) {
  return static_cast<uint32_t>(static_cast<Domain*>(ctx)->content.size());
}
canopen::SdoAbort dread(void* ctx, uint16_t, uint8_t, uint32_t offset, uint8_t* buf, uint16_t n) {
  Domain& d = *static_cast<Domain*>(ctx);
  if (static_cast<uint64_t>(offset) + n > d.content.size()) fail("server read past the object");
  memcpy(buf, d.content.data() + offset, n);
  return canopen::kSdoOk;
}
canopen::SdoAbort dbegin(void* ctx, uint16_t, uint8_t, uint32_t size, bool indicated) {
  Domain& d = *static_cast<Domain*>(ctx);
  if (indicated && size > 4096) return canopen::kAbortTooLong;
  d.staging.clear();
  d.announced = size;
  d.indicated = indicated;
  return canopen::kSdoOk;
}
canopen::SdoAbort dwrite(void* ctx, uint16_t, uint8_t, uint32_t offset, const uint8_t* p, uint16_t n) {
  Domain& d = *static_cast<Domain*>(ctx);
  if (offset != d.staging.size()) fail("server wrote the staging area out of order");
  if (offset + n > 4096) return canopen::kAbortTooLong;
  d.staging.insert(d.staging.end(), p, p + n);
  return canopen::kSdoOk;
}
canopen::SdoAbort dcommit(void* ctx, uint16_t, uint8_t, uint32_t size) {
  Domain& d = *static_cast<Domain*>(ctx);
  if (size != d.staging.size()) fail("commit size is not what was written");
  if (d.indicated && size != d.announced) fail("commit of a download shorter or longer than announced");
  d.content.swap(d.staging);
  ++d.commits;
  return canopen::kSdoOk;
}

bool discard(void*, const CanFrame&) {
  return true;
}

void fuzz_server(const uint8_t* data, size_t size) {
  uint32_t out_id = 0x580 + kNode;
  const CanSink sink{&check_sent, &out_id};
  ionode::IoNode io(CanSink{&discard, nullptr});
  io.start(kNode, 0);
  canopen::SdoServer server{};
  server.init(&io.od(), kNode);
  Domain domain;
  const canopen::SdoDomain table{&owns, &dsize, &dread, &dbegin, &dwrite, &dcommit, &domain};
  server.set_domain(&table);
  server.set_block_transfer(true);
  server.set_timeout_us(50000);
  uint32_t now = 1000;
  for (size_t i = 1; i + 9 <= size; i += 9) {
    now += data[i] * 1000u;
    CanFrame f{};
    f.id = 0x600 + kNode;
    f.dlc = 8;
    memcpy(f.data, data + i + 1, 8);
    const std::vector<uint8_t> before = domain.content;
    const int commits = domain.commits;
    server.process(now, sink);
    server.on_frame(f, now, sink);
    if (domain.commits == commits && domain.content != before) fail("object changed without a commit");
  }
  for (int k = 0; k < 200 && server.busy(); ++k) {
    now += 10000;
    server.process(now, sink);
  }
  if (server.busy()) fail("server still busy long after its timeout");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  if (data[0] & 0x08)
    fuzz_server(data, size);
  else
    fuzz_client(data, size);
  return 0;
}

#include "canopen/lab_api.h"

#include "canopen/sdo_client.h"

namespace mb2co {
namespace canopen {

namespace {

// The bound node and bus, and the one client sdo_read/sdo_write use (the
// lab API is not re-entrant, like od_bind).
Node* g_node = nullptr;
const LabBus* g_bus = nullptr;
SdoClient g_client;
bool g_transfer_running = false;
uint32_t g_last_abort = 0;

bool bound() {
  return g_node != nullptr && g_bus != nullptr;
}

// Hands every frame that arrived to the node; a frame on the running SDO
// transfer's response COB-ID goes to the client instead.
int drain(uint32_t now_us) {
  int handled = 0;
  CanFrame f;
  while (g_bus->receive(g_bus->ctx, &f)) {
    if (g_transfer_running && !f.extended() && f.id == g_client.response_id()) {
      g_client.on_frame(f, now_us, g_bus->send);
    } else {
      g_node->receive(f, now_us);
    }
    ++handled;
  }
  g_node->process(now_us);
  return handled;
}

// Runs the started transfer to its end, serving the node meanwhile.
int finish_transfer() {
  while (g_client.busy()) {
    const uint32_t now = g_bus->now_us(g_bus->ctx);
    drain(now);
    g_client.process(now, g_bus->send);
  }
  g_transfer_running = false;
  if (g_client.status() == SdoClient::kDone) return 0;
  g_last_abort = g_client.result();
  return kLabSdoFailed;
}

}  // namespace

void lab_bind(Node* node, const LabBus* bus) {
  g_node = node;
  g_bus = bus;
}

int pdo_send(uint16_t od_index) {
  if (!bound()) return kLabNotBound;
  uint8_t n;
  if (od_index >= 0x1800 && od_index < 0x1800 + kPdoCount) {
    n = static_cast<uint8_t>(od_index - 0x1800);
  } else if (od_index >= 0x1A00 && od_index < 0x1A00 + kPdoCount) {
    n = static_cast<uint8_t>(od_index - 0x1A00);
  } else {
    return kLabNoPdo;
  }
  // CiA 301: PDOs only in operational (a student's node that was never
  // started stays quiet, as a real one would).
  if (g_node->nmt_state() != kNmtOperational) return kLabNotOperational;
  switch (g_node->tpdos().send_now(n, g_bus->send, g_bus->now_us(g_bus->ctx))) {
    case Tpdos::kSentNow:
      return 0;
    case Tpdos::kSendNowInvalid:
      return kLabPdoInvalid;
    default:
      return kLabNotSent;
  }
}

int pdo_recv(void) {
  if (!bound()) return kLabNotBound;
  return drain(g_bus->now_us(g_bus->ctx));
}

int sdo_read(uint8_t node_id, uint16_t index, uint8_t sub, uint8_t* data, uint8_t* size) {
  if (!bound()) return kLabNotBound;
  if (g_transfer_running) return kLabBusy;
  g_client.init(node_id);
  if (!g_client.start_upload(index, sub, kSdoAuto, data, *size, g_bus->now_us(g_bus->ctx), g_bus->send))
    return kLabBusy;
  g_transfer_running = true;
  const int r = finish_transfer();
  if (r == 0) *size = static_cast<uint8_t>(g_client.transferred());
  return r;
}

int sdo_write(uint8_t node_id, uint16_t index, uint8_t sub, const uint8_t* data, uint8_t size) {
  if (!bound()) return kLabNotBound;
  if (g_transfer_running) return kLabBusy;
  g_client.init(node_id);
  if (!g_client.start_download(index, sub, kSdoAuto, data, size, g_bus->now_us(g_bus->ctx), g_bus->send))
    return kLabBusy;
  g_transfer_running = true;
  return finish_transfer();
}

uint32_t lab_sdo_abort(void) {
  return g_last_abort;
}

}  // namespace canopen
}  // namespace mb2co

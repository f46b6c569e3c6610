// The PDO and SDO functions of the course's labs (seed 000 §4.2–4.5), with
// the names and shapes the seed gives, on top of the node core: code written
// for the lab exercises compiles against mb2co. The OD functions of §3.3–3.5
// are in od_lab_api.h.
//
//   pdo_send(od_index)  builds TPDO n from its mapping (1A00h+n) and sends it
//                       now on its COB-ID (1800h+n sub 1); od_index names the
//                       TPDO by either record, 1800h+n or 1A00h+n.
//   pdo_recv()          hands every frame that arrived to the node: RPDOs
//                       write their mapped entries (the "leds"), a SYNC makes
//                       the synchronous TPDOs go out, NMT/SDO are served.
//   sdo_read/sdo_write  an SDO upload/download to another node through the
//                       portable SDO client (expedited or segmented), waiting
//                       until it ends: the node keeps being served meanwhile.
//
// The core never reads a clock or touches hardware: lab_bind() hands in the
// node and the bus (send, receive, clock) these functions use. Results: 0 on
// success, a negative LabError otherwise (the SDO abort code of a failed
// transfer: lab_sdo_abort()). Not re-entrant: one node is bound at a time,
// as in the lab; sdo_read/sdo_write block (the loop polls bus->receive and
// bus->now_us) until the transfer ends or its timeout aborts it.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/node.h"
#include "canopen/sdo_abort.h"

namespace mb2co {
namespace canopen {

enum LabError : int {
  kLabTooBig = -5,           ///< the data does not fit the caller's buffer / 255 bytes
  kLabNotBound = -6,         ///< lab_bind() was not called
  kLabNoPdo = -7,            ///< od_index is not 1800h-1803h or 1A00h-1A03h
  kLabPdoInvalid = -8,       ///< the TPDO's COB-ID is marked invalid (1800h+n/1 bit 31)
  kLabNotSent = -9,          ///< the bus refused the frame (transmit buffers full)
  kLabSdoFailed = -10,       ///< the transfer ended in an SDO abort: lab_sdo_abort()
  kLabBusy = -11,            ///< a transfer of this API is running (called re-entrantly)
  kLabNotOperational = -12,  ///< PDOs only in NMT operational (CiA 301)
};

/// What the lab functions use: all function pointers set, `ctx` theirs.
struct LabBus {
  CanSink send;                                 ///< frames out (the node's sink is fine)
  bool (*receive)(void* ctx, CanFrame* frame);  ///< a frame that arrived; false: none now
  uint32_t (*now_us)(void* ctx);                ///< a wrapping µs clock (micros())
  void* ctx;
};

/// Makes `node` and `bus` the ones the functions below use (nullptr
/// unbinds). Neither is owned; both must outlive their use.
void lab_bind(Node* node, const LabBus* bus);

int pdo_send(uint16_t od_index);
/// Returns the number of frames handed to the node (0: none had arrived).
int pdo_recv(void);
/// Reads node `node_id`'s entry into `data`; *size: in, the capacity; out,
/// the bytes read.
int sdo_read(uint8_t node_id, uint16_t index, uint8_t sub, uint8_t* data, uint8_t* size);
int sdo_write(uint8_t node_id, uint16_t index, uint8_t sub, const uint8_t* data, uint8_t size);
/// The abort code of the last sdo_read/sdo_write that returned kLabSdoFailed
/// (sent by us, e.g. the timeout 05040000h, or by the server).
uint32_t lab_sdo_abort(void);

}  // namespace canopen
}  // namespace mb2co

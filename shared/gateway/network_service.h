// FC 2Bh / MEI 0Dh behind the gateway's Modbus slave: SDO upload/download
// to any node (the service is the SDO client end itself: expedited and
// segmented, the data in the Modbus frame; canopen::SdoClient is the
// master's, with buffers, streams and block transfer), NMT commands to one node or
// all, and the network view (docs/gateway-network.md has the bytes, the
// rules and the timing).
//
// One request at a time, answered when done (the slave defers the answer):
// while a remote transfer runs, the slave answers its own registers at once,
// another 2Bh/0Dh gets exception 06, and the master's next frame drops the
// pending answer (the transfer runs to its end or its timeout). The
// gateway's own node id is served from the local OD without the bus.
//
// Memory: no data buffer of its own. Upload data go straight to the slave's
// frame buffer where the response is built; a download's data are read
// from the request in that buffer. A part of a multi-part download before
// the last carries whole segments (a multiple of 7 bytes: network_pdu.h),
// so the SDO client waits between parts at a segment boundary and nothing
// is carried over. RAM: the SDO client, the network view (kNetViewNodes)
// and ~30 bytes.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/node.h"
#include "canopen/od.h"
#include "canopen/sdo_abort.h"
#include "gateway/network_view.h"
#include "modbus/network_pdu.h"
#include "modbus/slave.h"

namespace mb2co {
namespace gateway {

/// The SDO client's time per step: a node that does not answer ends the
/// request with abort 05040000h this long after the request (or after the
/// previous segment).
constexpr uint32_t kNetSdoTimeoutUs = 500000u;
/// NetworkServiceState::step_ while the server is asked nothing (no command
/// byte's bits 7-5 equal it).
constexpr uint8_t kStepNone = 0x01;

/// The members of a NetworkService that start at zero: one block, value-
/// initialised by its constructor (one zero-fill instead of a store per
/// member; the phase's zero is kIdle).
struct NetworkServiceState {
  /// kDownloadEnded: an open download ended between parts (server abort,
  /// our timeout); result_ is the code for its next part. A remote transfer
  /// runs in the phases from kUpload on.
  enum Phase : uint8_t { kIdle, kDownloadEnded, kUpload, kDownload, kDownloadHeld };

  NetworkView view_;
  /// The request being served, besides what stays in the frame buffer (its
  /// answer is built there, in place, from it: answer_net_request()): the
  /// bytes it touches. An upload keeps the window [start_, start_ + count_)
  /// (count_: the bytes wanted, set_window()); a download part carries
  /// bytes [start_, start_ + count_) of the object.
  uint16_t start_;
  uint8_t count_;  ///< at most a response's data (net::kMaxSdoData)
  Phase phase_;

  // The SDO client end of a remote transfer (network_sdo.cpp): expedited
  // and segmented, upload and download, to node server_ (requests on
  // 600h + server_, responses on 580h + server_).
  uint32_t size_;  ///< the object's size: ours (download), the server's (upload; 0xFFFFFFFF while open)
  union {
    uint32_t pos_;  ///< an upload's object bytes stored
    /// A download's bytes of the part in hand acknowledged by the server
    /// (a part is at most a request's data: 8 bits; the object's offset is
    /// start_ + sent_).
    uint8_t sent_;
  };
  union {
    uint32_t deadline_us_;      ///< while it runs: the server's answer is due (kNetSdoTimeoutUs from the last
                                ///< progress)
    canopen::SdoAbort result_;  ///< once ended: how (kDownloadEnded: the code for the next part)
  };
  uint16_t index_;
  uint8_t sub_;
  uint8_t server_;
  /// What the server's next frame must be: its command byte's bits 7-5
  /// (60h download initiate, 20h download segment, 40h upload initiate, 00h
  /// upload segment); kStepNone (no such bits) while nothing is asked.
  uint8_t step_;
  uint8_t toggle_;  ///< 00h or 10h: the next segment's toggle bit
  union {
    bool size_known_;  ///< an upload's size was indicated
    /// The download part in hand is the object's last: its request's
    /// more-follows bit is clear (the parse checked that it then ends the
    /// object, and that a part before the last ends before it).
    bool last_part_;
  };
};

class NetworkService : private NetworkServiceState {
 public:
  /// All borrowed, outliving the service; frames go out through the
  /// node's sink. `now_us` is the owner's time of the frame or call being
  /// handled (the slave runs requests from inside its process() and
  /// on_char(): the owner sets it before them). `enabled` is the OD switch
  /// (2000h/10): 0 answers every request with exception 01.
  NetworkService(canopen::Node& node, canopen::ObjectDictionary& od, modbus::SlaveCore& slave,
                 const uint32_t& now_us, const uint8_t& enabled);

  /// Connects the service to the slave (the slave answers exception 01
  /// before). Call once, after construction.
  void attach() { slave_.set_net_handler(&handler_); }

  /// Every frame the node receives (heartbeats for the view, SDO responses).
  void on_can_frame(const CanFrame& f, uint32_t now_us);
  /// Timeouts and answers due: call with every Gateway::process().
  void process(uint32_t now_us);
  /// Lowers `d` to the SDO client's timeout, or now when work waits.
  void next_deadline(NextDeadline& d) const;

  bool transfer_running() const { return phase_ == kUpload || phase_ == kDownload; }
  /// True between the parts of a multi-part download (a segmented download
  /// is open at the server).
  bool download_open() const { return phase_ == kDownloadHeld; }
  /// The end of the bytes the request in hand carries or wants (a part's,
  /// a window's): object offset.
  uint32_t request_end() const { return static_cast<uint32_t>(start_) + count_; }
  const NetworkView& view() const { return view_; }

 private:
  static uint16_t handle(void* ctx, uint8_t* pdu, uint16_t pdu_length, uint16_t capacity);
  /// `ended`: how the download open before this request ended (kSdoOk: none).
  uint16_t on_request(uint8_t* pdu, uint16_t capacity, const modbus::NetMessage& m, canopen::SdoAbort ended);
  uint16_t nmt(const modbus::NetMessage& m);
  /// The network view's entries from node `first` on into the response.
  uint16_t list_view(uint8_t* pdu, uint16_t capacity, uint8_t first);
  /// The gateway's own node: the response (or the abort) in `pdu`; the
  /// window set, size_ becomes the object's (no transfer runs).
  uint16_t local_upload(uint8_t* pdu, uint16_t capacity, const modbus::NetMessage& m);
  canopen::SdoAbort local_download(const modbus::NetMessage& m);
  /// An upload's window, set once for every upload request, the own
  /// node's or a remote one's: count_ becomes the bytes wanted from start_ on, as
  /// many as the request asks for (`wanted`; 0: as many as a response of
  /// `capacity` bytes carries).
  void set_window(uint16_t capacity, uint16_t wanted);
  /// The upload response in `pdu` for an object of size_ bytes whose
  /// window's bytes are in place after the header and size (at most the
  /// window; fewer at the object's end, none beyond it); its length.
  uint16_t answer_window(uint8_t* pdu);
  /// True when `m` is the next part of the open download.
  bool continues_download(const modbus::NetMessage& m) const;
  /// The transfer ended with `code` (kSdoOk: done): answered, or between
  /// parts kept for the next part.
  void end(canopen::SdoAbort code);
  /// A download part all sent: answered; the download waits for the next.
  void hold_part();

  // ---- the SDO client end (network_sdo.cpp) ----
  /// Starts the remote transfer `m` asks for (the part's or window's
  /// bounds already in start_ and count_).
  void start_remote(const modbus::NetMessage& m);
  /// The next download segment, or hold_part() when its bytes are in a
  /// later part. `in_request`: called from handle(), the request in hand.
  void send_segment(bool in_request);
  /// True when the download goes in its initiate (1..4 bytes).
  bool expedited() const;
  /// The bytes of the download segment after the part's first sent_:
  /// 7, or fewer at the part's end (a part before the last ends at a
  /// segment boundary).
  uint8_t segment_bytes() const;
  /// A frame from the server: the next step, kSdoOk, or the code to abort with.
  canopen::SdoAbort on_response(const CanFrame& f);
  /// The server's next answer is due kNetSdoTimeoutUs from now (the
  /// request, or progress).
  void restart_timeout();
  /// Sends the abort frame `code` and ends the transfer with it.
  void abort(canopen::SdoAbort code);
  /// Sends an initiate (or abort) frame: `cmd`, the object, `value`.
  void send_mux(uint8_t cmd, uint32_t value);
  /// Upload bytes that belong at object offset `offset`: into the window.
  void store(uint32_t offset, const uint8_t* data, uint8_t n);

  canopen::Node& node_;
  canopen::ObjectDictionary& od_;
  modbus::SlaveCore& slave_;
  const uint32_t& now_us_;  ///< the owner's clock (one clock for the device)
  const uint8_t& enabled_;  ///< the OD switch 2000h/10
  modbus::NetRequestHandler handler_;
};

}  // namespace gateway
}  // namespace mb2co

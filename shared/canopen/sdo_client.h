// SDO client (CiA 301 §7.2.4): the master's side of an SDO channel to one
// server node. Expedited, segmented (toggle checked) and block transfer (sub-
// blocks of 1..127 segments, resent from the server's ackseq, CRC-16 when
// both ends support it, the protocol switch of block upload; only where
// MB2CO_CONFIG_SDO_BLOCK is defined, as in every host build: the Uno's gateway
// relays expedited and segmented transfers and has no flash for more), a timeout that
// aborts with 05040000h, and the abort code of every failure, sent by us or
// received from the server, as the result.
//
// Every transfer ends, whatever the server does: the timeout runs from the
// last progress (bytes moved or a step of the protocol), not from the last
// frame, so a server that keeps answering without moving on (empty
// segments, sub-blocks that never arrive in sequence) is timed out like a
// silent one; at most kBlockRepeatsMax sub-blocks in a row are sent or taken
// again (then 05040003h); more bytes than the server indicated end the
// transfer at the frame that shows them (06070012h), more than the caller's
// capacity likewise (05040005h), and an indicated size above the capacity is
// refused at the initiate. The codes are CANopenNode's (CO_SDOclient.c:
// 06070012h beyond the indicated size, 05040005h beyond its buffer); the
// timer from the last progress and the repeat bound are ours (CANopenNode
// restarts its timer on every frame and repeats sub-blocks without limit;
// CiA 301 leaves both open).
//
// One client per server node (the seed 002 "Node" object); several run at
// once, each with its own COB-IDs: nothing is global. No heap: the caller
// hands in the data, as a buffer or as an SdoData stream (a 1 MiB object to
// or from a file on Linux, a few bytes of RAM on the AVR).
//
// Use: start_upload()/start_download(), then hand in every frame on the
// response COB-ID (on_frame) and call process() at next_deadline(); when
// busy() turns false, result() says how it ended.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/sdo_abort.h"
#include "profiles/profile.h"
#if MB2CO_CONFIG_SDO_BLOCK
#include "canopen/sdo_block.h"
#endif
#include "canopen/sdo_domain.h"
#include "canopen/sdo_segment.h"

namespace mb2co {
namespace canopen {

/// How a transfer is carried out.
enum SdoMode : uint8_t {
  /// Download: expedited for 1..4 bytes, else segmented. Upload: as the
  /// server chooses (expedited or segmented).
  kSdoAuto,
  /// Download: segmented even for 0..4 bytes. Upload: as kSdoAuto.
  kSdoSegmented,
#if MB2CO_CONFIG_SDO_BLOCK
  /// Block transfer. An upload falls back to expedited or segmented when the
  /// server answers so (size <= the protocol switch threshold).
  kSdoBlock,
#endif
};

/// The members of an SdoClient that start at zero: one block, value-
/// initialised by its constructor (one zero-fill instead of a store per
/// member). The state enum's zero is kStIdle.
struct SdoClientState {
  enum State : uint8_t {
    kStIdle,
    kStDone,
    kStFailed,
    kStDownloadInitiate,  ///< waits for 60h
    kStDownloadSegment,   ///< waits for the ack of segment pos_
    kStDownloadWaiting,   ///< the next segment's bytes are not available yet
    kStUploadInitiate,    ///< waits for 4xh
    kStUploadSegment,     ///< waits for a segment
#if MB2CO_CONFIG_SDO_BLOCK
    kStBlockDownloadInitiate,
    kStBlockDownloadSub,  ///< sends a sub-block, waits for its ack
    kStBlockDownloadEnd,  ///< waits for A1h
    kStBlockUploadInitiate,
    kStBlockUploadSub,  ///< takes segments
    kStBlockUploadEnd,  ///< waits for the server's end frame
#endif
  };

  SdoData data_;
  uint8_t* buffer_;  ///< the caller's buffer (start_* with a pointer), else null
  uint32_t capacity_;
  uint32_t size_;
  uint32_t pos_;        ///< bytes moved: stored, or acknowledged by the server
  uint32_t available_;  ///< download: bytes [0, available_) of the data may be read
  uint32_t deadline_us_;
  SdoAbort result_;
#if MB2CO_CONFIG_SDO_BLOCK
  BlockSender sender_;
  BlockReceiver receiver_;
#endif
  uint16_t request_id_;
  uint16_t response_id_;
  uint16_t index_;
  uint8_t sub_;
#if MB2CO_CONFIG_SDO_BLOCK
  uint8_t block_size_;  ///< 0: kBlockSizeMax
  uint8_t pst_;
  uint8_t repeats_;  ///< sub-blocks in a row that had to be sent again (in part or whole)
  bool crc_;
#endif
  uint8_t toggle_;  ///< 0x00 or 0x10
  uint8_t seg_n_;   ///< data bytes of the download segment awaiting its ack
  State state_;
  bool size_known_;
  bool expedited_;
  bool server_abort_;
};

class SdoClient : private SdoClientState {
 public:
  SdoClient() : SdoClientState() {}

  /// How the last transfer stands.
  enum Status : uint8_t { kIdle, kBusy, kDone, kFailed };
  /// Default time the server may take to answer (CiA 301 leaves it open).
  static const uint32_t kDefaultTimeoutUs = 1000000u;

  /// The server is node `server_node_id` (1..127): requests on 600h+id,
  /// responses on 580h+id. Drops a transfer in progress without a word.
  void init(uint8_t server_node_id);
  /// Other COB-IDs (an SDO channel of 1280h-12FFh): client → server
  /// `request_id`, server → client `response_id`.
  void set_cob_ids(uint16_t request_id, uint16_t response_id) {
    request_id_ = request_id;
    response_id_ = response_id;
  }
  uint16_t request_id() const { return request_id_; }
  uint16_t response_id() const { return response_id_; }
  /// The server's answer must come within `us` of our last frame, and the
  /// transfer must make progress within `us` of its last progress.
  void set_timeout_us(uint32_t us) { timeout_us_ = us; }
  /// Whether a timeout sends its abort (05040000h) to the server; default
  /// true. False for a probe of a node id that may have no node (a scan):
  /// an abort there reaches nobody and, for every silent id at once, is a
  /// burst on the bus (python-canopen's scanner sends none either).
  void set_timeout_abort_sent(bool sent) { timeout_abort_sent_ = sent; }
#if MB2CO_CONFIG_SDO_BLOCK
  /// Sub-blocks in a row that may be repeated (the receiver took less than
  /// was sent); one more ends the transfer with 05040003h. A lost frame
  /// costs one repeat; a peer that never takes a sub-block whole would
  /// otherwise flood the bus until the timeout.
  static const uint8_t kBlockRepeatsMax = 8;
  /// Block size we offer as receiver of a block upload (1..127; others: 127).
  void set_block_size(uint8_t blksize) {
    block_size_ = blksize;
  }
  /// Protocol switch threshold of block upload: a server may answer an
  /// object of at most `bytes` with a plain upload (0: never; CiA 301).
  void set_switch_threshold(uint8_t bytes) {
    pst_ = bytes;
  }
#endif

  /// Reads (index, sub) into `buf`, at most `capacity` bytes (more: the
  /// transfer ends with 05040005h, out of memory, sent to the server at the
  /// initiate when the server indicates a larger size, else at the frame
  /// that brings more). `buf` must outlive the transfer. False when busy
  /// (nothing is sent).
  bool start_upload(uint16_t index, uint8_t sub, SdoMode mode, uint8_t* buf, uint32_t capacity,
                    uint32_t now_us, const CanSink& sink);
  /// Reads (index, sub) through `out` (its write() may refuse with a code),
  /// at most `capacity` bytes as above (0xFFFFFFFF: no limit of ours).
  bool start_upload(uint16_t index, uint8_t sub, SdoMode mode, const SdoData& out, uint32_t capacity,
                    uint32_t now_us, const CanSink& sink);
  /// Writes the `size` bytes of `data` (outliving the transfer) to (index, sub).
  bool start_download(uint16_t index, uint8_t sub, SdoMode mode, const uint8_t* data, uint32_t size,
                      uint32_t now_us, const CanSink& sink);
  /// Writes `size` bytes read through `in` to (index, sub).
  bool start_download(uint16_t index, uint8_t sub, SdoMode mode, const SdoData& in, uint32_t size,
                      uint32_t now_us, const CanSink& sink);
  /// A download whose data arrive while it runs (the gateway's multi-part
  /// writes): only bytes [0, `end`) may be read now (start_download: all).
  /// A segmented download stops before a segment that reaches beyond them
  /// (waiting_for_data()) and sends it once a later call makes them
  /// available. Its timeout keeps running from the server's last answer.
  void set_available(uint32_t end, const CanSink& sink);
  /// True while a segmented download waits for set_available().
  bool waiting_for_data() const {
    return state_ == kStDownloadWaiting;
  }

  /// A frame on response_id() (others, RTR frames and frames that are not
  /// 8 bytes long are ignored).
  void on_frame(const CanFrame& f, uint32_t now_us, const CanSink& sink);
  /// Times out a silent server (05040000h, sent and reported); sends what a
  /// full transmit queue held back.
  void process(uint32_t now_us, const CanSink& sink);
  /// Lowers `d` to the timeout of a transfer in progress (now when frames wait).
  void next_deadline(NextDeadline& d) const;
  /// Ends a transfer in progress with `code`, sent to the server (the
  /// master's watchdog, a user's cancel). Nothing when not busy.
  void abort(SdoAbort code, const CanSink& sink);

  bool busy() const {
    return state_ != kStIdle && state_ != kStDone && state_ != kStFailed;
  }
  Status status() const;
  /// kSdoOk after kDone; the abort code after kFailed.
  SdoAbort result() const {
    return result_;
  }
  /// True when result() came from the server's abort frame, false when we
  /// sent it.
  bool aborted_by_server() const {
    return server_abort_;
  }
  /// Bytes moved so far (acknowledged ones for a block download).
  uint32_t transferred() const {
    return pos_;
  }
  /// The size the server announced (upload) or ours (download); 0 with
  /// size_known() false when the server left it open.
  uint32_t size() const {
    return size_;
  }
  bool size_known() const {
    return size_known_;
  }
  /// The object of the current (or last) transfer.
  uint16_t index() const {
    return index_;
  }
  uint8_t subindex() const {
    return sub_;
  }
#if MB2CO_CONFIG_SDO_BLOCK
  /// True when the current/last transfer was a block transfer with CRC.
  bool crc_used() const {
    return crc_;
  }
#endif

 private:
  void begin(uint16_t index, uint8_t sub, uint32_t now_us);
  void send(const CanSink& sink, const uint8_t data[8]);
  /// Sends index, sub and 4 bytes after command `cmd`.
  void send_mux(const CanSink& sink, uint8_t cmd, uint32_t value);
  void send_download_segment(const CanSink& sink);
  void send_upload_request(const CanSink& sink);
  void finish(SdoAbort code, bool by_server);
  /// finish(kSdoOk, false): result_ and server_abort_ hold those values
  /// from begin() on (finish() is the only other writer, and it ends the
  /// transfer), so the state is all that changes.
  void succeed() {
    state_ = kStDone;
  }
  /// Handlers of a response in each state: kSdoOk or the code to abort with.
  SdoAbort on_response(const CanFrame& f, const CanSink& sink);
  SdoAbort on_upload_initiate(const CanFrame& f, const CanSink& sink);
  SdoAbort on_upload_segment(const CanFrame& f, const CanSink& sink);
#if MB2CO_CONFIG_SDO_BLOCK
  SdoAbort on_block_download(const CanFrame& f, const CanSink& sink);
  SdoAbort on_block_upload(const CanFrame& f, const CanSink& sink);
  /// Counts a sub-block that must be repeated (`repeat`) or resets the
  /// count; 05040003h once there were more than kBlockRepeatsMax in a row.
  SdoAbort count_repeat(bool repeat);
#endif
  bool mux_matches(const CanFrame& f) const;

  static SdoAbort buffer_write(void* ctx, uint32_t offset, const uint8_t* data, uint16_t n);
  static SdoAbort buffer_read(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n);

  uint32_t timeout_us_ = kDefaultTimeoutUs;
  bool timeout_abort_sent_ = true;
};

}  // namespace canopen
}  // namespace mb2co

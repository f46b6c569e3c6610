// SDO block transfer (CiA 301 §7.2.4.3.9-16), the parts both ends share:
// the sending half (the segments of a sub-block, numbered 1..blksize, sent
// again from the peer's ackseq), the receiving half (segments taken in
// sequence only, the ack, the end phase with the unused bytes of the last
// segment), and the CRC both ends agree on. SdoClient uses both halves; the
// SdoServer uses them in host builds (MB2CO_CONFIG_SDO_BLOCK).
//
// Frame layout (byte 0; bytes 1..3 are index and sub-index where named):
//   download  initiate  C: 110 00 cc s 0, size      S: 101 00 sc 00, blksize
//             segment   C: c seqno(7 bits), 7 data bytes
//             ack       S: 101 000 10, ackseq, blksize
//             end       C: 110 n(3) 0 1, crc        S: 101 000 01
//   upload    initiate  C: 101 00 cc 00, blksize, pst
//                       S: 110 00 sc s 0, size (or a plain upload answer
//                          when size <= pst: the protocol switch)
//             start     C: 101 000 11
//             segment   S: c seqno, 7 data bytes
//             ack       C: 101 000 10, ackseq, blksize
//             end       S: 110 n(3) 0 1, crc        C: 101 000 01
// n: bytes of the last segment without data. The abort frame 80h reads as
// "seqno 0, c = 1", which no segment has: it is told apart from segments.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/sdo_abort.h"
#include "canopen/sdo_domain.h"

namespace mb2co {
namespace canopen {

/// Largest number of segments in a sub-block (blksize 1..127).
static const uint8_t kBlockSizeMax = 127;
/// Data bytes in one block segment.
static const uint8_t kBlockSegmentBytes = 7;

/// CRC-16 of CiA 301 block transfers: polynomial 1021h (CCITT), initial
/// value 0, no reflection, no final XOR ("123456789" gives 31C3h). Chains:
/// crc = sdo_crc16(crc, next bytes).
uint16_t sdo_crc16(uint16_t crc, const uint8_t* data, uint32_t n);

/// The sending end of a block transfer: a sub-block at a time, every byte
/// read from `data` again when it is resent. The CRC covers each byte once,
/// at its first transmission (a resent sub-block starts below crc_end_).
class BlockSender {
 public:
  /// A transfer of `size` bytes from `data` begins at offset 0.
  void start(const SdoData& data, uint32_t size);
  /// The next sub-block holds at most `blksize` (1..127) segments, from the
  /// first byte not yet acknowledged.
  void begin_sub_block(uint8_t blksize);
  /// Sends the sub-block's segments not yet sent, on `cob_id`, until the
  /// sub-block is out or the sink refuses a frame (pending() stays true:
  /// call again later). An abort code when `data` could not be read.
  SdoAbort pump(uint16_t cob_id, const CanSink& sink);
  /// True while segments of the current sub-block are still to be sent.
  bool pending() const { return sent_ < blksize_ && last_seq_ == 0; }
  /// Segments of the current sub-block sent so far.
  uint8_t sent() const { return sent_; }
  /// The receiver's ack of the sub-block: `ackseq` segments arrived in
  /// sequence (the next sub-block starts after them), next sub-blocks hold
  /// `blksize` segments. 05040003h / 05040002h when either is out of range.
  SdoAbort on_ack(uint8_t ackseq, uint8_t blksize);
  /// True once the segment with the last byte (c = 1) is acknowledged.
  bool finished() const { return finished_; }
  /// Bytes of the last segment that carry no data (the end phase's n).
  uint8_t unused() const;
  /// CRC of the bytes sent so far (all of them once finished()).
  uint16_t crc() const { return crc_; }
  /// Bytes the receiver has acknowledged (a progress bar).
  uint32_t acked() const { return acked_; }

 private:
  SdoData data_;
  uint32_t size_;
  uint32_t acked_;    ///< bytes acknowledged: the current sub-block starts here
  uint32_t crc_end_;  ///< bytes covered by crc_
  uint16_t crc_;
  uint8_t blksize_;   ///< segments in the current sub-block, at most
  uint8_t sent_;      ///< segments of the current sub-block sent
  uint8_t last_seq_;  ///< seqno of the segment with c = 1 in this sub-block; 0: not sent
  bool finished_;
};

/// The receiving end: takes the segments of a sub-block in sequence and
/// ignores the rest (a lost segment makes the ack name the last one in
/// sequence, and the sender resends from there). The latest segment is held
/// back until the next arrives or the end phase says how many of its bytes
/// are data, so `data` only ever gets real bytes. Limit: the ack needs the
/// sub-block's last seqno (or c = 1) to arrive; if exactly that frame is
/// lost, nothing triggers the ack and the transfer ends at the timeout
/// (05040000h). CiA 301 defines no ack without it.
class BlockReceiver {
 public:
  /// A transfer into `data` begins; more than `limit` bytes are refused
  /// with `over_code`; sub-blocks of `blksize` (1..127) segments.
  void start(const SdoData& data, uint32_t limit, SdoAbort over_code, uint8_t blksize);
  /// A segment frame (8 bytes, not the abort frame 80h). *ack becomes true
  /// when the sub-block is over (its last seqno or c = 1 arrived): send the
  /// ack with ackseq(), then call next_sub_block(). An abort code when the
  /// bytes could not be stored.
  SdoAbort on_segment(const CanFrame& f, bool* ack);
  /// The last seqno received in sequence in the current sub-block (0: none).
  uint8_t ackseq() const { return seq_; }
  /// After the ack went out: the next sub-block, `blksize` segments from 1.
  void next_sub_block(uint8_t blksize) {
    seq_ = 0;
    blksize_ = blksize;
  }
  /// True once the segment with c = 1 has been taken in sequence.
  bool complete() const { return last_; }
  /// The end phase: `unused` bytes of the held last segment carry no data.
  /// Stores the rest; 05040001h when the last segment never came.
  SdoAbort finish(uint8_t unused);
  /// Bytes stored into `data` so far (all of them after finish()).
  uint32_t received() const { return stored_; }
  /// True when the bytes known to be data are more than `limit`: those
  /// stored and the held segment's 7 unless it is the last one (a segment
  /// with c = 0 is full, CiA 301). A sender going beyond a limit shows at
  /// the segment that does, not one segment later when it is stored.
  bool beyond(uint32_t limit) const {
    if (stored_ > limit) return true;
    return held_valid_ && !last_ && kBlockSegmentBytes > limit - stored_;
  }
  /// CRC of the bytes stored so far.
  uint16_t crc() const { return crc_; }

 private:
  SdoAbort store(const uint8_t* bytes, uint8_t n);

  SdoData data_;
  uint32_t limit_;
  uint32_t stored_;
  SdoAbort over_code_;
  uint16_t crc_;
  uint8_t held_[kBlockSegmentBytes];  ///< the latest segment in sequence, not yet stored
  uint8_t seq_;
  uint8_t blksize_;
  bool held_valid_;
  bool last_;
};

}  // namespace canopen
}  // namespace mb2co

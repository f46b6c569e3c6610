// The client side of one Modbus/TCP exchange on a connected socket, for the
// programs whose codecs check RTU ADUs (mb2co-master --via-modbus tcp:,
// mb2co-plant --tcp): the request ADU (address, PDU, CRC) goes out as its
// MBAP frame with the caller's transaction id (modbus/tcp_framer.h), frames
// are read whole by their length field, one with another transaction id is
// a late answer to an abandoned request and skipped (Modbus Messaging on
// TCP/IP Implementation Guide §4.4.1.3), and the answer comes back as an
// RTU ADU (unit id as the address, CRC appended) for the same codec. For
// what libmodbus 3.1 cannot receive (FC 2Bh: it takes the length from the
// function code). Host-only (POSIX sockets); header-only.
#pragma once
#include <errno.h>
#include <poll.h>
#include <stdint.h>
#include <sys/socket.h>
#include <time.h>

#include "modbus/tcp_framer.h"

namespace mb2co {

enum class MbapOutcome : uint8_t {
  kAnswer,       ///< the answer with our transaction id, as an RTU ADU
  kSilence,      ///< nothing of an answer by the deadline
  kPartial,      ///< part of a frame by the deadline
  kBadFrame,     ///< a length field outside 2..254, or not protocol 0: the stream is lost
  kClosed,       ///< the server closed the connection (or it broke)
  kSendFailed,   ///< the request could not be written (or is no ADU)
  kInterrupted,  ///< `interrupted` said so while waiting
};

/// CLOCK_MONOTONIC in ms (the deadlines below).
inline int64_t mbap_now_ms() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000 + ts.tv_nsec / 1000000;
}

/// Sends `request` (an RTU ADU of `length` bytes) on `fd` as transaction
/// `transaction` and waits until `deadline_ms` for its answer, written to
/// `adu` (room for modbus::kMaxAduBytes) with its length in *adu_length.
/// `interrupted` (may be null) is asked between waits of at most the rest.
inline MbapOutcome mbap_exchange(int fd, const uint8_t* request, uint16_t length, uint16_t transaction,
                                 int64_t deadline_ms, uint8_t* adu, uint16_t* adu_length,
                                 bool (*interrupted)() = nullptr) {
  uint8_t frame[modbus::kMaxMbapFrameBytes];
  const uint16_t n = modbus::mbap_from_rtu(frame, sizeof frame, request, length, transaction);
  if (n == 0 || send(fd, frame, n, MSG_NOSIGNAL) != static_cast<ssize_t>(n)) return MbapOutcome::kSendFailed;
  for (;;) {
    uint16_t have = 0;
    uint16_t want = modbus::kMbapHeaderBytes;
    while (have < want) {
      if (interrupted != nullptr && interrupted()) return MbapOutcome::kInterrupted;
      const int64_t left = deadline_ms - mbap_now_ms();
      pollfd p{fd, POLLIN, 0};
      const int ready = left > 0 ? poll(&p, 1, static_cast<int>(left)) : 0;
      if (ready < 0 && errno == EINTR) continue;  // `interrupted` tells
      if (ready <= 0) return have == 0 ? MbapOutcome::kSilence : MbapOutcome::kPartial;
      const ssize_t got = recv(fd, frame + have, want - have, 0);
      if (got < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (got <= 0) return MbapOutcome::kClosed;
      have = static_cast<uint16_t>(have + got);
      if (have == modbus::kMbapHeaderBytes && (want = modbus::mbap_frame_length(frame)) == 0)
        return MbapOutcome::kBadFrame;
    }
    if (modbus::read_mbap_header(frame).transaction != transaction) continue;  // a late answer
    *adu_length = modbus::rtu_from_mbap(adu, modbus::kMaxAduBytes, frame, have);
    return *adu_length != 0 ? MbapOutcome::kAnswer : MbapOutcome::kBadFrame;
  }
}

}  // namespace mb2co

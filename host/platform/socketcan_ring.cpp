// The io_uring path of SocketCanPort: see socketcan_ring.h.
#include "platform/socketcan_ring.h"

#include <errno.h>

#if MB2CO_HAVE_LIBURING
#include <liburing.h>
#include <string.h>
#include <sys/mman.h>
#endif

namespace mb2co {
namespace linux_port {

#if MB2CO_HAVE_LIBURING

namespace {

/// Submission queue entries: every send slot and the receive fit at once,
/// so stage() never finds the queue full.
constexpr unsigned kSqEntries = 512;
/// Completion queue entries: every send's completion and every buffer's
/// record fit at once, so no completion is ever lost to an overflow.
constexpr unsigned kCqEntries = 1024;
static_assert(SocketCanRing::kTxSlots + 1 <= kSqEntries,
              "a submission's sends and the receive fit the queue");
static_assert(SocketCanRing::kTxSlots + SocketCanRing::kRxBuffers + 1 <= kCqEntries,
              "the completions of everything in flight fit the queue");
/// One received record: io_uring_recvmsg_out, the control messages, a can_frame.
constexpr size_t kRxBufferBytes = 128;
constexpr uint16_t kBufferGroup = 0;
/// user_data of the receive; a send's is its slot.
constexpr uint64_t kReceiveTag = ~uint64_t{0};
/// Longest wait (µs) for the sends' completions alone: they never block
/// (MSG_DONTWAIT), the bound only keeps a surprise from hanging the owner.
constexpr uint32_t kSendWaitUs = 100000;

}  // namespace

struct SocketCanRing::Impl {
  io_uring ring{};
  bool ring_up = false;
  int sock_fd = -1;
  io_uring_buf_ring* buffers = nullptr;  ///< kRxBuffers entries, page-aligned (mmap)
  size_t buffers_bytes = 0;
  msghdr layout{};  ///< the multishot's record layout: no name, control_bytes of control
  bool armed = false;
  io_uring_sqe* chain_tail = nullptr;  ///< the last staged send, linked to the next one
  size_t next_slot = 0;                ///< slots go round in order, as sends complete in order
  alignas(16) unsigned char rx[kRxBuffers][kRxBufferBytes] = {};
  struct ::can_frame tx[kTxSlots] = {};  ///< what the kernel reads until each send completes

  ~Impl() {
    if (ring_up) io_uring_queue_exit(&ring);  // cancels the receive before its buffers go
    if (buffers != nullptr) munmap(buffers, buffers_bytes);
  }

  void give_back(unsigned short bid, int offset) {
    io_uring_buf_ring_add(buffers, rx[bid], kRxBufferBytes, bid, io_uring_buf_ring_mask(kRxBuffers), offset);
  }

  bool arm() {
    io_uring_sqe* sqe = io_uring_get_sqe(&ring);
    if (sqe == nullptr) return false;
    io_uring_prep_recvmsg_multishot(sqe, sock_fd, &layout, 0);
    sqe->flags |= IOSQE_BUFFER_SELECT;
    sqe->buf_group = kBufferGroup;
    io_uring_sqe_set_data64(sqe, kReceiveTag);
    armed = true;
    return true;
  }
};

SocketCanRing::SocketCanRing(Impl* impl) : impl_(impl) {}
SocketCanRing::~SocketCanRing() = default;

std::unique_ptr<SocketCanRing> SocketCanRing::create(int sock_fd, size_t control_bytes, const char** what,
                                                     int* err) {
  *err = 0;
  std::unique_ptr<Impl> impl(new Impl);
  impl->sock_fd = sock_fd;
  io_uring_params params{};
  params.flags = IORING_SETUP_CQSIZE;
  params.cq_entries = kCqEntries;
  int r = io_uring_queue_init_params(kSqEntries, &impl->ring, &params);
  if (r < 0) {
    *what = "io_uring_setup";
    *err = -r;
    return nullptr;
  }
  impl->ring_up = true;
  if ((params.features & IORING_FEAT_EXT_ARG) == 0) {
    *what = "io_uring without timed waits (Linux < 5.11)";
    return nullptr;
  }
  impl->buffers_bytes = kRxBuffers * sizeof(io_uring_buf);
  void* mem = mmap(nullptr, impl->buffers_bytes, PROT_READ | PROT_WRITE, MAP_ANONYMOUS | MAP_PRIVATE, -1, 0);
  if (mem == MAP_FAILED) {
    *what = "mmap of the io_uring buffer ring";
    *err = errno;
    return nullptr;
  }
  impl->buffers = static_cast<io_uring_buf_ring*>(mem);
  io_uring_buf_ring_init(impl->buffers);
  io_uring_buf_reg reg{};
  reg.ring_addr = reinterpret_cast<uintptr_t>(impl->buffers);
  reg.ring_entries = kRxBuffers;
  reg.bgid = kBufferGroup;
  r = io_uring_register_buf_ring(&impl->ring, &reg, 0);
  if (r < 0) {
    *what = "io_uring buffer ring (Linux < 5.19)";
    *err = -r;
    return nullptr;
  }
  for (size_t i = 0; i < kRxBuffers; ++i)
    impl->give_back(static_cast<unsigned short>(i), static_cast<int>(i));
  io_uring_buf_ring_advance(impl->buffers, kRxBuffers);
  impl->layout.msg_controllen = control_bytes;
  if (control_bytes + sizeof(io_uring_recvmsg_out) + sizeof(can_frame) > kRxBufferBytes) {
    *what = "control messages larger than a receive buffer";
    return nullptr;
  }
  impl->arm();
  r = io_uring_submit(&impl->ring);
  if (r < 0) {
    *what = "io_uring_enter";
    *err = -r;
    return nullptr;
  }
  // A kernel without multishot recvmsg (Linux < 6.0) refuses it at once.
  io_uring_cqe* cqe = nullptr;
  if (io_uring_peek_cqe(&impl->ring, &cqe) == 0 && cqe->user_data == kReceiveTag && cqe->res < 0 &&
      cqe->res != -ENOBUFS && (cqe->flags & IORING_CQE_F_MORE) == 0) {
    *what = "io_uring multishot recvmsg (Linux < 6.0)";
    *err = -cqe->res;
    return nullptr;
  }
  return std::unique_ptr<SocketCanRing>(new SocketCanRing(impl.release()));
}

int SocketCanRing::fd() const {
  return impl_->ring.ring_fd;
}

bool SocketCanRing::ready() const {
  return io_uring_cq_ready(&impl_->ring) != 0;
}

bool SocketCanRing::stage(const struct ::can_frame& frame) {
  if (in_flight_ + staged_ >= kTxSlots) return false;
  io_uring_sqe* sqe = io_uring_get_sqe(&impl_->ring);
  if (sqe == nullptr) return false;  // not with kSqEntries > kTxSlots; the frame stays with the owner
  const size_t slot = impl_->next_slot;
  impl_->next_slot = (slot + 1) % kTxSlots;
  impl_->tx[slot] = frame;
  io_uring_prep_send(sqe, impl_->sock_fd, &impl_->tx[slot], sizeof frame, MSG_DONTWAIT);
  sqe->flags |= IOSQE_IO_LINK;  // cleared on the submission's last send
  io_uring_sqe_set_data64(sqe, slot);
  impl_->chain_tail = sqe;
  ++staged_;
  return true;
}

int SocketCanRing::submit(uint32_t wait_us) {
  Impl& im = *impl_;
  if (im.chain_tail != nullptr) {
    im.chain_tail->flags &= static_cast<unsigned char>(~IOSQE_IO_LINK);  // the receive is no link of it
    im.chain_tail = nullptr;
  }
  if (!im.armed) im.arm();
  in_flight_ += staged_;
  staged_ = 0;
  int r = 0;
  if (io_uring_cq_ready(&im.ring) != 0 || (in_flight_ == 0 && wait_us == 0)) {
    // Completions wait already (the owner takes them first) or nothing is
    // to be waited for: submit only. Sends never block, so they complete
    // inside this call all the same.
    r = io_uring_submit_and_get_events(&im.ring);
  } else {
    // Until every send completed and, when asked, one record came.
    const bool for_frame = wait_us != 0;
    const uint32_t bound_us = for_frame ? wait_us : kSendWaitUs;
    __kernel_timespec ts{static_cast<long long>(bound_us / 1000000u),
                         static_cast<long long>(bound_us % 1000000u) * 1000};
    io_uring_cqe* first = nullptr;
    r = io_uring_submit_and_wait_timeout(
        &im.ring, &first, static_cast<unsigned>(in_flight_) + (for_frame ? 1u : 0u), &ts, nullptr);
  }
  if (r >= 0 || r == -ETIME || r == -EAGAIN) return 0;
  return -r;
}

void SocketCanRing::reap(RingCompletions& to) {
  Impl& im = *impl_;
  unsigned head = 0;
  unsigned seen = 0;
  int returned = 0;
  io_uring_cqe* cqe = nullptr;
  io_uring_for_each_cqe(&im.ring, head, cqe) {
    if (cqe->user_data != kReceiveTag) {
      if (cqe->res < 0) to.on_refused(im.tx[cqe->user_data % kTxSlots], -cqe->res);
      --in_flight_;
      ++seen;
      continue;
    }
    const bool has_buffer = (cqe->flags & IORING_CQE_F_BUFFER) != 0;
    if (has_buffer && cqe->res >= 0) {
      const auto bid = static_cast<unsigned short>(cqe->flags >> IORING_CQE_BUFFER_SHIFT);
      io_uring_recvmsg_out* out = io_uring_recvmsg_validate(im.rx[bid % kRxBuffers], cqe->res, &im.layout);
      msghdr control{};
      const void* payload = nullptr;
      size_t len = 0;
      if (out != nullptr) {
        control.msg_control = reinterpret_cast<unsigned char*>(out + 1) + im.layout.msg_namelen;
        control.msg_controllen = out->controllen;
        payload = io_uring_recvmsg_payload(out, &im.layout);
        len = io_uring_recvmsg_payload_length(out, cqe->res, &im.layout);
      }
      const bool truncated = out == nullptr || (out->flags & MSG_TRUNC) != 0;
      if (!to.on_record(payload, len, truncated, control)) break;  // this one and the rest wait
      im.give_back(bid % kRxBuffers, returned++);
    } else if (cqe->res < 0 && cqe->res != -ENOBUFS) {
      to.on_receive_error(-cqe->res);  // ENOBUFS: all buffers were out; armed again below
    }
    if ((cqe->flags & IORING_CQE_F_MORE) == 0) im.armed = false;
    ++seen;
  }
  if (returned != 0) io_uring_buf_ring_advance(im.buffers, returned);
  io_uring_cq_advance(&im.ring, seen);
}

#else  // built without liburing: create() says so, the port keeps its calls

struct SocketCanRing::Impl {};

SocketCanRing::SocketCanRing(Impl* impl) : impl_(impl) {}
SocketCanRing::~SocketCanRing() = default;

std::unique_ptr<SocketCanRing> SocketCanRing::create(int, size_t, const char** what, int* err) {
  *what = "built without liburing (scripts/deps.sh installs liburing-dev)";
  *err = 0;
  return nullptr;
}
int SocketCanRing::fd() const {
  return -1;
}
bool SocketCanRing::ready() const {
  return false;
}
bool SocketCanRing::stage(const struct ::can_frame&) {
  return false;
}
int SocketCanRing::submit(uint32_t) {
  return ENOSYS;
}
void SocketCanRing::reap(RingCompletions&) {}

#endif

}  // namespace linux_port
}  // namespace mb2co

// `serve` through a gateway (--via-modbus): its transfers and NMT commands
// block on the gateway link (one Modbus request at a time), so they run on
// a worker thread of their own and the loop keeps serving the clients. The
// worker takes what was asked meanwhile as one batch, in order (transfers
// of different nodes taking turns, an NMT command after the transfers
// before it), and hands the batch back; an eventfd in the loop's poll()
// wakes the loop, which calls the callbacks. A job belongs to the worker
// from the moment it took it until it handed it back: a cancelled one is
// then dropped unseen (a gateway transfer cannot be aborted half-way).
#pragma once
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "bus_loop.h"
#include "cli_options.h"
#include "serve_backend.h"
#include "serve_jobs.h"
#include "transport.h"

namespace mb2co {
namespace master {

class ThreadServeBackend : public ServeBackend, public PollWatcher {
 public:
  /// `transport` is open; from now on only the worker uses it. Add this
  /// to the loop as a watcher.
  ThreadServeBackend(const Options& o, Transport& transport);
  /// Stops the worker after its batch (a gateway request ends within its
  /// response timeout) and joins it.
  ~ThreadServeBackend() override;
  ThreadServeBackend(const ThreadServeBackend&) = delete;
  ThreadServeBackend& operator=(const ThreadServeBackend&) = delete;

  Ticket sdo(SdoJob job, SdoDone done) override;
  Ticket nmt(uint8_t command, uint8_t node, NmtDone done) override;
  void cancel(Ticket ticket) override;
  /// Neither: the gateway runs the transfer with its own SDO client.
  bool block_transfer() const override { return false; }
  bool sdo_timeout() const override { return false; }
  std::string describe() const override { return where_; }

  void poll_fds(std::vector<pollfd>* fds) override;
  void on_poll(const pollfd* fds, size_t n, uint32_t now_us) override;
  void on_frame(const CanFrame&, uint32_t, const CanSink&) override {}
  void process(uint32_t, const CanSink&) override {}
  void next_deadline(NextDeadline&) const override {}

 private:
  void submit(BackendJob* job);
  void worker();
  /// Runs one batch in order on a fresh network of transfers.
  void run_batch(const std::vector<BackendJob*>& batch);

  const Options options_;
  Transport& transport_;
  std::string where_;
  JobTable jobs_;  ///< the loop's thread only
  std::mutex mutex_;
  std::condition_variable work_;
  std::deque<BackendJob*> inbox_;  ///< asked, not yet taken by the worker (mutex_)
  std::vector<BackendJob*> done_;  ///< handed back by the worker (mutex_)
  bool stop_ = false;              ///< mutex_
  int wake_fd_ = -1;               ///< eventfd: the worker handed a batch back
  std::thread thread_;
};

}  // namespace master
}  // namespace mb2co

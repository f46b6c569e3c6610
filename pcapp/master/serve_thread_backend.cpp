#include "serve_thread_backend.h"

#include <signal.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <utility>

namespace mb2co {
namespace master {

ThreadServeBackend::ThreadServeBackend(const Options& o, Transport& transport)
    : options_(o),
      transport_(transport),
      where_("gateway " + o.gateway_port + ":" + std::to_string(o.gateway_slave)),
      wake_fd_(eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {
  // SIGINT and SIGTERM go to the loop's thread (its poll() returns); the
  // worker sees the flag at its next wait (platform/stop_signal.h).
  sigset_t stop, old;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop, &old);
  thread_ = std::thread(&ThreadServeBackend::worker, this);
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
}

ThreadServeBackend::~ThreadServeBackend() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_.notify_one();
  thread_.join();
  if (wake_fd_ >= 0) close(wake_fd_);
}

void ThreadServeBackend::submit(BackendJob* job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    inbox_.push_back(job);
  }
  work_.notify_one();
}

ServeBackend::Ticket ThreadServeBackend::sdo(SdoJob job, SdoDone done) {
  BackendJob* j = jobs_.add_sdo(std::move(job), std::move(done));
  submit(j);
  return j->ticket;
}

ServeBackend::Ticket ThreadServeBackend::nmt(uint8_t command, uint8_t node, NmtDone done) {
  BackendJob* j = jobs_.add_nmt(command, node, std::move(done));
  submit(j);
  return j->ticket;
}

void ThreadServeBackend::cancel(Ticket ticket) {
  BackendJob* j = jobs_.find(ticket);
  if (j == nullptr) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = std::find(inbox_.begin(), inbox_.end(), j);
    if (it != inbox_.end()) {
      inbox_.erase(it);
      jobs_.erase(ticket);
      return;
    }
  }
  // With the worker (or back, not yet delivered): delivered to nobody.
  j->sdo_done = nullptr;
  j->nmt_done = nullptr;
}

void ThreadServeBackend::poll_fds(std::vector<pollfd>* fds) {
  fds->push_back(pollfd{wake_fd_, POLLIN, 0});
}

void ThreadServeBackend::on_poll(const pollfd* fds, size_t n, uint32_t) {
  if (n == 0 || !(fds[0].revents & POLLIN)) return;
  uint64_t count = 0;
  if (read(wake_fd_, &count, sizeof count) < 0) return;  // EAGAIN: someone drained it
  std::vector<BackendJob*> back;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    back.swap(done_);
  }
  for (BackendJob* j : back) jobs_.deliver(j->ticket);
}

void ThreadServeBackend::run_batch(const std::vector<BackendJob*>& batch) {
  std::unique_ptr<TransferNetwork> network = transport_.transfers(options_);
  const auto run = [&network] {
    if (!network->run(nullptr)) network->abort_all(canopen::kAbortGeneral);  // SIGINT: serve ends
  };
  for (BackendJob* j : batch) {
    if (!j->is_nmt) {
      network->queue(&j->transfer);
      continue;
    }
    run();  // the transfers asked before it first
    const Status sent = transport_.nmt(static_cast<canopen::NmtCommand>(j->nmt_command), j->nmt_node);
    if (!sent) j->nmt_failure = sent.message();
  }
  run();
}

void ThreadServeBackend::worker() {
  for (;;) {
    std::vector<BackendJob*> batch;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      work_.wait(lock, [this] { return stop_ || !inbox_.empty(); });
      if (stop_) return;
      batch.assign(inbox_.begin(), inbox_.end());
      inbox_.clear();
    }
    run_batch(batch);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      done_.insert(done_.end(), batch.begin(), batch.end());
    }
    const uint64_t one = 1;
    if (write(wake_fd_, &one, sizeof one) < 0) {
      // An eventfd counter cannot overflow at one per batch: never.
    }
  }
}

}  // namespace master
}  // namespace mb2co

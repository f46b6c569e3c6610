#include "serve_can_backend.h"

#include <utility>

namespace mb2co {
namespace master {

CanServeBackend::CanServeBackend(const Options& o, Transport& transport)
    : transport_(transport), iface_(o.iface), network_(transport.transfers(o)) {}

ServeBackend::Ticket CanServeBackend::sdo(SdoJob job, SdoDone done) {
  BackendJob* j = jobs_.add_sdo(std::move(job), std::move(done));
  const Ticket ticket = j->ticket;
  // Only noted: the network may end a transfer inside queue() (refused at
  // once), and a callback must never run inside sdo().
  j->transfer.on_done = [this, ticket](Transfer&) { finished_.push_back(ticket); };
  network_->queue(&j->transfer);
  return ticket;
}

ServeBackend::Ticket CanServeBackend::nmt(uint8_t command, uint8_t node, NmtDone done) {
  BackendJob* j = jobs_.add_nmt(command, node, std::move(done));
  const Status sent = transport_.nmt(static_cast<canopen::NmtCommand>(command), node);
  if (!sent) j->nmt_failure = sent.message();
  finished_.push_back(j->ticket);
  return j->ticket;
}

void CanServeBackend::cancel(Ticket ticket) {
  BackendJob* j = jobs_.find(ticket);
  if (j == nullptr) return;
  // A transfer still queued or running ends here (a running one aborted on
  // the bus, the node's next one started); one finished but not delivered
  // is only forgotten.
  if (!j->is_nmt && !j->transfer.finished && !network_->cancel(&j->transfer, canopen::kAbortStore)) {
    j->sdo_done = nullptr;  // not the network's to end: delivered to nobody
    return;
  }
  jobs_.erase(ticket);
}

void CanServeBackend::process(uint32_t, const CanSink&) {
  std::vector<Ticket> due;
  due.swap(finished_);
  for (const Ticket t : due) jobs_.deliver(t);  // gone when cancelled meanwhile
}

}  // namespace master
}  // namespace mb2co

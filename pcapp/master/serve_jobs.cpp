#include "serve_jobs.h"

#include <utility>

namespace mb2co {
namespace master {

BackendJob* JobTable::add() {
  std::unique_ptr<BackendJob> job(new BackendJob);
  job->ticket = next_++;
  BackendJob* p = job.get();
  jobs_[p->ticket] = std::move(job);
  return p;
}

BackendJob* JobTable::add_sdo(SdoJob job, ServeBackend::SdoDone done) {
  BackendJob* j = add();
  Transfer& t = j->transfer;
  t.node = job.node;
  t.index = job.index;
  t.sub = job.sub;
  t.upload = job.upload;
  t.mode = job.block ? canopen::kSdoBlock : canopen::kSdoAuto;
  t.data = std::move(job.data);
  t.timeout_us = job.timeout_ms * 1000u;
  t.max_bytes = kValueMaxBytes;
  j->sdo_done = std::move(done);
  return j;
}

BackendJob* JobTable::add_nmt(uint8_t command, uint8_t node, ServeBackend::NmtDone done) {
  BackendJob* j = add();
  j->is_nmt = true;
  j->nmt_command = command;
  j->nmt_node = node;
  j->nmt_done = std::move(done);
  return j;
}

BackendJob* JobTable::find(ServeBackend::Ticket ticket) {
  const auto it = jobs_.find(ticket);
  return it == jobs_.end() ? nullptr : it->second.get();
}

void JobTable::deliver(ServeBackend::Ticket ticket) {
  const auto it = jobs_.find(ticket);
  if (it == jobs_.end()) return;
  const std::unique_ptr<BackendJob> job = std::move(it->second);
  jobs_.erase(it);
  if (job->is_nmt) {
    if (job->nmt_done) job->nmt_done(job->nmt_failure);
  } else if (job->sdo_done) {
    job->sdo_done(outcome_of(job->transfer));
  }
}

SdoOutcome outcome_of(const Transfer& t) {
  SdoOutcome o;
  o.ok = t.ok();
  o.abort_code = static_cast<uint32_t>(t.result);
  o.gateway_error = t.gateway_error;
  if (t.link_down && o.gateway_error.empty()) o.gateway_error = "the gateway does not answer";
  if (o.ok) o.data = t.data;
  return o;
}

}  // namespace master
}  // namespace mb2co

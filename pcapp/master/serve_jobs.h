// What both backends of `serve` keep for each request: the transfer (or NMT
// command), its ticket and its callback, in a table owned by the loop's
// thread. A job is delivered (its callback called, the job freed) once; a
// cancelled job is erased and never delivered.
#pragma once
#include <stdint.h>

#include <map>
#include <memory>
#include <string>

#include "serve_backend.h"
#include "transfer_network.h"

namespace mb2co {
namespace master {

struct BackendJob {
  ServeBackend::Ticket ticket = 0;
  bool is_nmt = false;
  uint8_t nmt_command = 0;
  uint8_t nmt_node = 0;
  std::string nmt_failure;  ///< "" when the NMT frame went out
  Transfer transfer;        ///< the SDO transfer (not for NMT)
  ServeBackend::SdoDone sdo_done;
  ServeBackend::NmtDone nmt_done;
};

class JobTable {
 public:
  /// A new job for `job` (its Transfer set up, at most kValueMaxBytes).
  BackendJob* add_sdo(SdoJob job, ServeBackend::SdoDone done);
  BackendJob* add_nmt(uint8_t command, uint8_t node, ServeBackend::NmtDone done);
  /// nullptr when delivered or erased.
  BackendJob* find(ServeBackend::Ticket ticket);
  void erase(ServeBackend::Ticket ticket) { jobs_.erase(ticket); }
  /// Takes the job out and calls its callback with its result; nothing when
  /// it is gone. The callback may add and cancel jobs.
  void deliver(ServeBackend::Ticket ticket);
  size_t size() const { return jobs_.size(); }

 private:
  BackendJob* add();
  std::map<ServeBackend::Ticket, std::unique_ptr<BackendJob>> jobs_;
  ServeBackend::Ticket next_ = 1;
};

/// The outcome a client is told of a finished transfer.
SdoOutcome outcome_of(const Transfer& t);

}  // namespace master
}  // namespace mb2co

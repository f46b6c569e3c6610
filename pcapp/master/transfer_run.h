// Running a command's queued SDO transfers to their end, over whatever
// transport carries them, with a progress bar on a terminal and a clean
// abort on SIGINT (the nodes are told: 08000000h).
#pragma once
#include <memory>
#include <ostream>

#include "cli_options.h"
#include "transfer_network.h"
#include "transport.h"

namespace mb2co {
namespace master {

/// The SDO side of a command: the transport's network of transfers.
class TransferRun {
 public:
  TransferRun(const Options& o, Transport& transport) : network_(transport.transfers(o)) {}
  TransferNetwork& network() { return *network_; }
  /// Runs until nothing is queued or running. False when interrupted
  /// (everything was aborted).
  bool run();
  /// Shows a progress bar for the transfers of `node` on `err` (a terminal).
  void show_progress(uint8_t node, std::ostream* err) {
    progress_node_ = node;
    progress_out_ = err;
  }

 private:
  class Progress;
  std::unique_ptr<TransferNetwork> network_;
  uint8_t progress_node_ = 0;
  std::ostream* progress_out_ = nullptr;
};

/// The exit code for a failed transfer: no answer (timeout, node lost) → 4,
/// a refusal → 1.
int exit_code_of(const Transfer& t);

}  // namespace master
}  // namespace mb2co

// `serve` on its own SocketCAN interface: every transfer goes to the
// master's network of SDO clients on the bus loop (the one-shot commands'
// SdoNetwork, each node's queue running at once), NMT frames go out at
// once. Callbacks are called from this service's process(), after the
// frames of a pass, never inside sdo()/nmt(). A cancelled transfer that
// runs is aborted on the bus (08000020h) and the node's next one starts.
#pragma once
#include <memory>

#include "bus_loop.h"
#include "cli_options.h"
#include "serve_backend.h"
#include "serve_jobs.h"
#include "transport.h"

namespace mb2co {
namespace master {

class CanServeBackend : public ServeBackend, public BusService {
 public:
  /// `transport` is open and has a bus(); its network of transfers joins
  /// the bus loop now, this service after it (add it to the loop).
  CanServeBackend(const Options& o, Transport& transport);

  Ticket sdo(SdoJob job, SdoDone done) override;
  Ticket nmt(uint8_t command, uint8_t node, NmtDone done) override;
  void cancel(Ticket ticket) override;
  bool block_transfer() const override { return true; }
  bool sdo_timeout() const override { return true; }
  std::string describe() const override { return "SocketCAN " + iface_; }

  void on_frame(const CanFrame&, uint32_t, const CanSink&) override {}
  /// Calls the callbacks of what finished.
  void process(uint32_t now_us, const CanSink& sink) override;
  void next_deadline(NextDeadline& d) const override {
    if (!finished_.empty()) d.now();
  }

 private:
  Transport& transport_;
  std::string iface_;
  JobTable jobs_;  ///< outlives network_, which points into it
  std::unique_ptr<TransferNetwork> network_;
  std::vector<Ticket> finished_;  ///< to deliver at the next process()
};

}  // namespace master
}  // namespace mb2co

#include "can_transport.h"

#include <cstdio>

#include "canopen/master/nmt_master.h"
#include "sdo_network.h"

namespace mb2co {
namespace master {

Status CanTransport::open(const Options& o) {
  Status opened = bus_.open(o.iface.c_str());
  if (opened && o.verbose) std::fprintf(stderr, "mb2co-master: %s\n", bus_.port().io_note());
  return opened;
}

namespace {

/// An SdoNetwork on the bus for as long as the command's transfers live.
class CanTransfers : public TransferNetwork {
 public:
  CanTransfers(const Options& o, BusLoop& bus) : bus_(bus), net_(o.timeout_ms * 1000u, o.watchdog_ms) {
    bus_.add(&net_);
  }
  ~CanTransfers() override { bus_.remove(&net_); }

  void queue(Transfer* t) override { net_.queue(t); }
  size_t pending() const override { return net_.pending(); }
  void progress(uint8_t node, uint32_t* moved, uint32_t* size) const override {
    net_.progress(node, moved, size);
  }
  void drop_queued(uint8_t node, canopen::SdoAbort code) override { net_.drop_queued(node, code); }
  void abort_all(canopen::SdoAbort code) override { net_.abort_all(code, bus_.sink()); }
  bool cancel(Transfer* t, canopen::SdoAbort code) override { return net_.cancel(t, code, bus_.sink()); }

  bool run(ProgressHook* progress) override {
    Redraw redraw(progress);
    if (progress) bus_.add(&redraw);
    const auto done = [this] { return net_.pending() == 0; };
    while (!done() && !bus_.interrupted()) bus_.run_until(done, BusLoop::kLongestRunUs);
    if (progress) bus_.remove(&redraw);
    return done();
  }

 private:
  /// The progress hook as a service of the loop.
  class Redraw : public BusService {
   public:
    explicit Redraw(ProgressHook* hook) : hook_(hook) {}
    void on_frame(const CanFrame&, uint32_t, const CanSink&) override {}
    void process(uint32_t now_us, const CanSink&) override { hook_->update(now_us); }
    void next_deadline(NextDeadline& d) const override { d.at(hook_->next_us()); }

   private:
    ProgressHook* hook_;
  };

  BusLoop& bus_;
  SdoNetwork net_;
};

}  // namespace

std::unique_ptr<TransferNetwork> CanTransport::transfers(const Options& o) {
  return std::unique_ptr<TransferNetwork>(new CanTransfers(o, bus_));
}

Status CanTransport::nmt(canopen::NmtCommand command, uint8_t node) {
  canopen::NmtMaster nmt(bus_.sink());
  if (nmt.command(command, node)) return Status::ok();
  return Status::failure("the CAN interface refused the frame: " + std::string(bus_.port().last_io_error()));
}

}  // namespace master
}  // namespace mb2co

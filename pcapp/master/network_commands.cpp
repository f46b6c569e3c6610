// nmt and sync: the two unconfirmed services a master sends on its own.
#include <cstdio>

#include "bus_loop.h"
#include "canopen/master/sync_producer.h"
#include "commands.h"
#include "exit_codes.h"
#include "periodic_command.h"

namespace mb2co {
namespace master {

int fail(std::ostream& err, int code, const std::string& why) {
  err << "mb2co-master: " << why << "\n";
  return code;
}

int open_transport(const Options& o, Transport& transport, std::ostream& err) {
  const Status opened = transport.open(o);
  return opened ? kExitOk : fail(err, kExitBus, opened.message());
}

namespace {

struct NmtName {
  const char* word;
  canopen::NmtCommand command;
};
const NmtName kNmtNames[] = {{"start", canopen::kNmtStart},
                             {"stop", canopen::kNmtStop},
                             {"preop", canopen::kNmtEnterPreOperational},
                             {"reset", canopen::kNmtResetNode},
                             {"reset-comm", canopen::kNmtResetCommunication}};

/// The SYNC producer as a bus service; counts what it sent.
class SyncService : public BusService {
 public:
  SyncService(canopen::SyncProducer* producer, std::ostream* out, bool json)
      : producer_(producer), out_(out), json_(json) {}
  void on_frame(const CanFrame&, uint32_t, const CanSink&) override {}
  void process(uint32_t now_us, const CanSink& sink) override {
    uint8_t counter = 0;
    if (!producer_->process(now_us, sink, &counter)) return;
    if (sent_ == 0) first_us_ = now_us;
    ++sent_;
    const double at_ms = static_cast<double>(now_us - first_us_) / 1000.0;
    char line[96];
    if (json_)
      std::snprintf(line, sizeof line, "{\"sync\":%u,\"counter\":%u,\"at_ms\":%.3f}\n", sent_, counter,
                    at_ms);
    else
      std::snprintf(line, sizeof line, "sync %u counter=%u at_ms=%.3f\n", sent_, counter, at_ms);
    *out_ << line << std::flush;
  }
  void next_deadline(NextDeadline& d) const override { producer_->next_deadline(d); }
  unsigned sent() const { return sent_; }

 private:
  canopen::SyncProducer* producer_;
  std::ostream* out_;
  bool json_;
  unsigned sent_ = 0;
  uint32_t first_us_ = 0;
};

}  // namespace

int nmt_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  const std::vector<std::string>& w = o.args.operands;
  // Two operands: the table's min_operands and max_operands (cli_options.cpp).
  const NmtName* name = nullptr;
  for (const NmtName& n : kNmtNames)
    if (w[0] == n.word) name = &n;
  if (!name)
    return fail(err, kExitUsage,
                "nmt: the NMT command must be start, stop, preop, reset or reset-comm, got \"" + w[0] + "\"");
  uint8_t node = 0;
  const Status s = parse_node_id(w[1], true, &node);
  if (!s) return fail(err, kExitUsage, "nmt: " + s.message());
  if (const int code = open_transport(o, transport, err)) return code;
  const Status sent = transport.nmt(name->command, node);
  if (!sent) return fail(err, kExitBus, "nmt: " + sent.message());
  const std::string who = node == 0 ? "all" : std::to_string(node);
  if (o.json)
    out << "{\"nmt\":\"" << name->word << "\",\"node\":" << (node == 0 ? "\"all\"" : who) << "}\n";
  else
    out << "nmt " << name->word << " " << who << "\n";
  return kExitOk;
}

int sync_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  if (!transport.bus()) return fail(err, kExitUsage, "sync: " + needs_can_frames("sync"));
  BusLoop& bus = *transport.bus();
  PeriodicOptions p;
  if (const int code = read_periodic_options("sync", o, 0x80, &p, err)) return code;
  const uint64_t overflow = o.args.uint("--overflow", 0);  // range checked by the parser
  if (overflow == 1) return fail(err, kExitUsage, "sync: --overflow 1 is not allowed (CiA 301: 0 or 2..240)");
  if (const int code = open_transport(o, transport, err)) return code;
  canopen::SyncProducer producer;
  // One SYNC alone needs a period too: the producer sends at its start.
  producer.configure(static_cast<uint32_t>(p.cob_id),
                     static_cast<uint32_t>(p.period_ms ? p.period_ms : 1) * 1000u,
                     static_cast<uint8_t>(overflow));
  SyncService service(&producer, &out, o.json);
  bus.add(&service);
  if (const int code = run_until_done(bus, [&] { return service.sent() >= p.count; })) return code;
  if (producer.send_failures())
    return fail(err, kExitBus,
                "sync: the CAN interface refused a SYNC: " + std::string(bus.port().last_io_error()));
  return kExitOk;
}

}  // namespace master
}  // namespace mb2co

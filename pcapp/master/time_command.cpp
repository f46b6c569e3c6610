// time: the master as CiA 301 TIME producer. Each frame carries the host's
// wall clock (UTC) read when the frame is built, so the stamp is late by
// the send path only (the nodes' consumers take the frame's arrival as
// that instant: canopen/time_stamp.h).
#include <cstdio>

#include "bus_loop.h"
#include "canopen/frame_out.h"
#include "canopen/time_of_day.h"
#include "commands.h"
#include "exit_codes.h"
#include "periodic_command.h"
#include "wall_time.h"

namespace mb2co {
namespace master {

namespace {

/// Sends a TIME frame at once and then every period; counts what it sent.
class TimeService : public BusService {
 public:
  TimeService(uint16_t cob_id, uint32_t period_us, std::ostream* out, bool json)
      : cob_id_(cob_id), period_us_(period_us), out_(out), json_(json) {}
  void on_frame(const CanFrame&, uint32_t, const CanSink&) override {}
  void process(uint32_t now_us, const CanSink& sink) override {
    if (sent_ != 0 && now_us - last_us_ < period_us_) return;
    // Whole periods from the first frame; a late pass sends once, no burst.
    last_us_ = sent_ == 0 || now_us - last_us_ >= 2 * period_us_ ? now_us : last_us_ + period_us_;
    canopen::TimeOfDay t;
    if (!time_of_day_of_unix_ms(wall_clock_unix_ms(), &t)) {
      clock_out_of_range_ = true;
      return;
    }
    uint8_t data[canopen::kTimeFrameLength];
    canopen::encode_time_of_day(t, data);
    if (!canopen::send_frame(sink, cob_id_, canopen::kTimeFrameLength, data)) {
      send_failed_ = true;
      return;
    }
    ++sent_;
    char line[128];
    const std::string utc = utc_text(t);
    if (json_)
      std::snprintf(line, sizeof line, "{\"time\":%u,\"utc\":\"%s\",\"days\":%u,\"ms\":%u}\n", sent_,
                    utc.c_str(), t.days, static_cast<unsigned>(t.ms));
    else
      std::snprintf(line, sizeof line, "time %u %s days=%u ms=%u\n", sent_, utc.c_str(), t.days,
                    static_cast<unsigned>(t.ms));
    *out_ << line << std::flush;
  }
  void next_deadline(NextDeadline& d) const override {
    if (sent_ == 0) return d.now();
    const uint32_t elapsed_us = d.now_us() - last_us_;
    d.in(elapsed_us < period_us_ ? period_us_ - elapsed_us : 0);
  }
  unsigned sent() const { return sent_; }
  bool stopped() const { return clock_out_of_range_ || send_failed_; }
  bool clock_out_of_range() const { return clock_out_of_range_; }

 private:
  uint16_t cob_id_;
  uint32_t period_us_;
  std::ostream* out_;
  bool json_;
  unsigned sent_ = 0;
  uint32_t last_us_ = 0;  ///< when the last frame was due (bus loop µs)
  bool clock_out_of_range_ = false;
  bool send_failed_ = false;
};

}  // namespace

int time_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  if (!transport.bus()) return fail(err, kExitUsage, "time: " + needs_can_frames("time"));
  BusLoop& bus = *transport.bus();
  PeriodicOptions p;
  if (const int code = read_periodic_options("time", o, canopen::kTimeCobIdDefault, &p, err)) return code;
  if (const int code = open_transport(o, transport, err)) return code;
  TimeService service(static_cast<uint16_t>(p.cob_id), static_cast<uint32_t>(p.period_ms) * 1000u, &out,
                      o.json);
  bus.add(&service);
  if (const int code = run_until_done(bus, [&] { return service.sent() >= p.count || service.stopped(); }))
    return code;
  if (service.clock_out_of_range())
    return fail(err, kExitRefused,
                "time: the host clock is outside what TIME can carry (1984-01-01 to 2163)");
  if (service.stopped())
    return fail(err, kExitBus,
                "time: the CAN interface refused a TIME frame: " + std::string(bus.port().last_io_error()));
  return kExitOk;
}

}  // namespace master
}  // namespace mb2co

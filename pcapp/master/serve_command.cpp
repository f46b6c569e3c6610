// serve: the master as a long-running service speaking CiA 309-3's ASCII
// mapping (as CANopenNode's canopend does for cocomm) on a local or TCP
// socket, to many clients at once (docs/mb2co-master.md, "serve"). The bus
// loop carries everything: the CAN socket (or the gateway's worker), the
// listening socket and every client.
#include <time.h>

#include <iostream>
#include <memory>

#include "commands.h"
#include "exit_codes.h"
#include "platform/stop_signal.h"
#include "serve_can_backend.h"
#include "serve_events.h"
#include "serve_server.h"
#include "serve_thread_backend.h"

namespace mb2co {
namespace master {

namespace {

/// canopend's log prefix: the local time of the event.
std::string stamped(const std::string& line) {
  const time_t now = time(nullptr);
  tm local;
  localtime_r(&now, &local);
  char stamp[32];
  strftime(stamp, sizeof stamp, "%Y-%m-%d %H:%M:%S: ", &local);
  return stamp + line;
}

}  // namespace

int serve_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  ListenAddress address;
  const Status parsed = parse_listen(o.args.get("--listen", kServeListenDefault), &address);
  if (!parsed) return fail(err, kExitUsage, "serve: " + parsed.message());
  if (o.json) return fail(err, kExitUsage, "serve: --json is not for serve (its clients speak CiA 309-3)");
  ServerLimits limits;
  // Ranges checked by the parser (the table in cli_options.cpp).
  limits.max_clients = o.args.uint("--max-clients", limits.max_clients);
  limits.idle_ms = static_cast<uint32_t>(o.args.uint("--idle-timeout", kServeIdleDefaultMs));
  limits.session.sdo_timeout_ms = o.timeout_ms;
  limits.session.max_value = kValueMaxBytes;
  const uint16_t consumer_ms = static_cast<uint16_t>(o.args.uint("--heartbeat", 1000));
  if (const int code = open_transport(o, transport, err)) return code;

  BusLoop gateway_loop;  // through a gateway: a loop without a CAN socket
  BusLoop* bus = transport.bus();
  std::unique_ptr<ServeBackend> backend;
  BusService* backend_service = nullptr;  // the same object, as the loop sees it
  std::unique_ptr<NetworkEvents> events;
  if (bus != nullptr) {
    auto* can = new CanServeBackend(o, transport);
    backend.reset(can);
    backend_service = can;
    bus->add(can);
  } else {
    port::catch_stop_signals();
    bus = &gateway_loop;
    auto* thread = new ThreadServeBackend(o, transport);
    backend.reset(thread);
    backend_service = thread;
    bus->add_watcher(thread);
  }
  ServeServer server(*backend, limits, out);
  const Status listening = server.listen(address);
  if (!listening) return fail(err, kExitBus, "serve: " + listening.message());
  if (transport.bus() != nullptr) {
    events.reset(new NetworkEvents(consumer_ms, [&server, &out](const std::string& line) {
      const std::string text = stamped(line);
      out << text << "\n" << std::flush;
      server.event(text);
    }));
    bus->add(events.get());
  }
  bus->add_watcher(&server);
  out << "mb2co-master serve: listening on " << server.where() << " (net 1, " << backend->describe()
      << ", at most " << limits.max_clients << " clients, idle timeout "
      << (limits.idle_ms ? std::to_string(limits.idle_ms) + " ms" : std::string("off")) << ")\n"
      << std::flush;
  if (!loopback_only(address))
    err << "mb2co-master: serve: " << server.where()
        << " is reachable from other machines, and CiA 309-3 has no authentication: whoever reaches it "
           "commands the CAN network\n";
  while (!bus->interrupted()) bus->run_until([] { return false; }, BusLoop::kLongestRunUs);
  bus->remove(&server);
  if (events) bus->remove(events.get());
  bus->remove(backend_service);
  out << "mb2co-master serve: stopped\n" << std::flush;
  return kExitOk;
}

}  // namespace master
}  // namespace mb2co

#include "options.h"

#include <QCommandLineParser>
#include <QCoreApplication>
#include <type_traits>

#include "host/cli_messages.h"
#include "host/cli_values.h"

namespace mb2co {
namespace pcapp {

namespace {
const char kDescription[] =
    "The PC side of one bottling station (seed 000 §9-11): plant simulator and controller,\n"
    "talking Modbus/RTU to the station's Arduino gateway (or Modbus/TCP to mb2co-node --tcp).\n"
    "  station (default)  run the station: START/STOP/STOP2 on the Arduino, RUN state to it\n"
    "  latency            latency lab: a button mirrored to the lab LED, delay per press";

const char kProgram[] = "mb2co-plant";

std::string word(const QString& text) {
  return text.toStdString();
}

/// Qt's parse errors in the wording of docs/cli.md (shared/host/cli_messages.h).
Status parse_error(const QCommandLineParser& p, const QList<QCommandLineOption>& all) {
  if (!p.unknownOptionNames().isEmpty()) {
    const QString name = p.unknownOptionNames().front();
    std::vector<std::string> known = {"--help", "--version"};
    for (const QCommandLineOption& opt : all) known.push_back("--" + word(opt.names().back()));
    return Status::failure(
        cli::unknown_option(kProgram, "", word((name.size() == 1 ? "-" : "--") + name), known));
  }
  // Qt says "Missing value after '--port'." and "Unexpected value after '--plain'.".
  const QString text = p.errorText();
  const QString name = text.section('\'', 1, 1);
  if (text.startsWith("Missing value after '")) return Status::failure(word(name) + " needs a value");
  if (text.startsWith("Unexpected value after '")) return Status::failure(word(name) + " takes no value");
  return Status::failure(word(text) + " " + cli::try_help(kProgram, ""));
}

bool standard_baud(long b) {
  for (long s : {1200L, 2400L, 4800L, 9600L, 19200L, 38400L, 57600L, 115200L, 230400L, 460800L, 500000L,
                 921600L, 1000000L}) {
    if (b == s) return true;
  }
  return false;
}
}  // namespace

Status parse_options(const QStringList& args, AppOptions& o) {
  QCommandLineParser p;
  p.setApplicationDescription(QString::fromUtf8(kDescription));
  const QCommandLineOption help = p.addHelpOption();
  const QCommandLineOption version = p.addVersionOption();
  p.addPositionalArgument("mode", "station (default) or latency", "[station|latency]");
  const QCommandLineOption port("port", "Serial device of the gateway (default: the one Arduino on USB).",
                                "PATH");
  const QCommandLineOption tcp("tcp",
                               "Modbus/TCP to mb2co-node --tcp instead of a serial port (a bare PORT: "
                               "127.0.0.1); --slave is then the unit id (default 255).",
                               "HOST:PORT");
  const QCommandLineOption list("list-ports", "List serial ports (Arduinos marked) and exit.");
  const QCommandLineOption baud("baud", "Baud rate (default 115200).", "N", "115200");
  const QCommandLineOption parity("parity", "Parity N, E or O, or none, even, odd (default N).", "P", "N");
  const QCommandLineOption slave("slave", "Modbus address of the gateway 1..247 (default 1).", "N", "1");
  const QCommandLineOption cycle("cycle-ms",
                                 "Control cycle = plant step in ms, 1..1000 (default: the config's "
                                 "step_ms, else 20).",
                                 "MS");
  const QCommandLineOption config("config", "Plant config file (docs/plant.md).", "FILE");
  const QCommandLineOption timeout("timeout-ms",
                                   "Modbus response timeout 1..10000 ms (default: the longest exchange "
                                   "at --baud + the gateway's reply time + 25 ms; 36 at 115200).",
                                   "MS");
  const QCommandLineOption retries("retries", "Retries after a timeout or bad frame 0..10 (default 2).", "N",
                                   "2");
  const QCommandLineOption boot("boot-wait-ms",
                                "Wait after opening the port for the Uno's boot loader, "
                                "0..60000 (default 2000 for an Arduino port, 0 otherwise).",
                                "MS");
  const QCommandLineOption no_reset("no-reset-wait",
                                    "Do not wait for a boot loader (same as --boot-wait-ms 0).");
  const QCommandLineOption reconnect("reconnect-max-ms",
                                     "Longest pause between reconnection attempts, "
                                     "100..600000 (default 5000).",
                                     "MS", "5000");
  const QCommandLineOption log("log", "Every cycle's I/O to FILE.csv or FILE.jsonl.", "FILE");
  const QCommandLineOption plain("plain", "Log lines even on a terminal (no live status line).");
  const QCommandLineOption cycles("cycles", "Stop after N cycles (default: run until SIGINT/SIGTERM).", "N");
  const QCommandLineOption remote("remote",
                                  "latency: the button is on the watched remote station (by PDO), measured "
                                  "from its own edge stamp on the TIME-synchronised clock.");
  const QCommandLineOption drift("drift-ppm",
                                 "latency --remote: most two station clocks run apart, 0..100000 ppm "
                                 "(default 100), for the clock offset's uncertainty.",
                                 "PPM", "100");
  const QCommandLineOption button("button", "latency: START, STOP or STOP2 (default START).", "NAME",
                                  "START");
  const QCommandLineOption presses("presses", "latency: stop after N measured presses.", "N");
  const QCommandLineOption csv("csv", "latency: CSV of every press.", "FILE");
  // Bash completion asks for the words (docs/cli.md); not in --help.
  QCommandLineOption list_options("list-options", "Words for bash completion.");
  list_options.setFlags(QCommandLineOption::HiddenFromHelp);
  const QList<QCommandLineOption> all = {port,   tcp,     list,    baud,  parity,   slave,     cycle,
                                         config, timeout, retries, boot,  no_reset, reconnect, log,
                                         plain,  cycles,  remote,  drift, button,   presses,   csv};
  p.addOptions(all);
  p.addOption(list_options);

  if (!p.parse(args)) return parse_error(p, all);
  if (p.isSet(help)) {
    o.exit_text = p.helpText();
    return Status::ok();
  }
  if (p.isSet(version)) {
    o.exit_text = QCoreApplication::applicationName() + " " + QCoreApplication::applicationVersion() + "\n";
    return Status::ok();
  }
  if (p.isSet(list_options)) {
    o.exit_text = "station\nlatency\n";
    for (const QCommandLineOption& opt : all) {
      o.exit_text += "--" + opt.names().back() + (opt.valueName().isEmpty() ? " flag\n" : " value\n");
    }
    o.exit_text += "--help flag\n--version flag\n";
    return Status::ok();
  }
  for (const QCommandLineOption& opt : all) {
    if (p.values(opt).size() > 1) {
      return Status::failure(QString("--" + opt.names().back() + " given twice").toStdString());
    }
  }
  const QStringList pos = p.positionalArguments();
  if (pos.size() > 1) {
    return Status::failure("unexpected argument \"" + word(pos[1]) + "\" " + cli::try_help(kProgram, ""));
  }
  if (pos.size() == 1 && pos[0] != "station" && pos[0] != "latency") {
    const std::string near = cli::nearest_word(word(pos[0]), {"station", "latency"});
    return Status::failure("unknown mode \"" + word(pos[0]) + "\" (" +
                           (near.empty() ? "station or latency" : "did you mean " + near + "?") + ") " +
                           cli::try_help(kProgram, ""));
  }
  o.latency = pos.size() == 1 && pos[0] == "latency";
  o.list_ports = p.isSet(list);
  o.port = p.value(port);
  o.plain = p.isSet(plain);
  o.remote = p.isSet(remote);
  o.config = p.value(config);
  o.log = p.value(log);
  o.csv = p.value(csv);

  Status bad;
  auto number = [&](const QCommandLineOption& opt, uint64_t lo, uint64_t hi, auto& field) {
    if (!p.isSet(opt) && opt.defaultValues().isEmpty()) return true;
    uint64_t v = 0;
    bad = cli::parse_uint("--" + word(opt.names().front()), word(p.value(opt)), lo, hi, &v);
    if (!bad) return false;
    field = static_cast<std::remove_reference_t<decltype(field)>>(v);
    return true;
  };
  if (!number(baud, 1200, 4000000, o.baud) || !number(slave, 1, 247, o.slave) ||
      !number(cycle, 1, 1000, o.cycle_ms) || !number(timeout, 1, 10000, o.timeout_ms) ||
      !number(retries, 0, 10, o.retries) || !number(boot, 0, 60000, o.boot_wait_ms) ||
      !number(reconnect, 100, 600000, o.reconnect_max_ms) || !number(cycles, 1, 4000000000L, o.cycles) ||
      !number(presses, 1, 1000000, o.presses) || !number(drift, 0, 100000, o.drift_ppm)) {
    return bad;
  }
  if (!standard_baud(o.baud)) {
    return Status::failure(
        cli::bad_value("--baud", "a standard rate such as 9600, 19200, 115200", word(p.value(baud))));
  }
  Status parity_ok = cli::parse_parity("--parity", p.value(parity).toStdString(), &o.parity);
  if (!parity_ok) return parity_ok;
  if (p.isSet(no_reset)) {
    if (p.isSet(boot)) {
      return Status::failure("--no-reset-wait and --boot-wait-ms exclude each other");
    }
    o.boot_wait_ms = 0;
  }
  const QString b = p.value(button).toUpper();
  o.button = b == "START" ? 1 : b == "STOP" ? 2 : b == "STOP2" ? 4 : 0;
  if (o.button == 0) {
    return Status::failure(cli::bad_value("--button", "START, STOP or STOP2", word(p.value(button))));
  }
  const bool latency_only = p.isSet(remote) || p.isSet(button) || p.isSet(presses) || p.isSet(csv);
  if (!o.latency && latency_only) {
    return Status::failure(
        "--remote, --button, --presses and --csv belong to the latency mode (mb2co-plant latency ...)");
  }
  if (p.isSet(drift) && !o.remote) return Status::failure("--drift-ppm belongs to latency --remote");
  if (o.latency && p.isSet(config)) {
    return Status::failure("--config belongs to the station mode");
  }
  if (p.isSet(tcp)) {
    for (const QCommandLineOption* serial : {&port, &list, &baud, &parity}) {
      if (p.isSet(*serial))
        return Status::failure(
            QString("--" + serial->names().front() + " is the serial line's: not with --tcp").toStdString());
    }
    Status where = parse_tcp_address("--tcp", p.value(tcp).toStdString(), false, &o.tcp);
    if (!where) return where;
    o.on_tcp = true;
    if (!p.isSet(slave)) o.slave = 255;  // a server addressed by its IP address
  }
  return Status::ok();
}

}  // namespace pcapp
}  // namespace mb2co

// mb2co-od: prints a node's Object Dictionary as Markdown or as an EDS file.
//   mb2co-od --node ionode|gateway --format md|eds|registers [--profile P]
// One build per gateway profile (shared/profiles): this program describes
// the OD of the profile it was built with (mb2co-od: linux) and hands a
// request for another profile to that profile's build, mb2co-od-<profile>,
// next to it.
#include <limits.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <string>

#include "gateway/gateway.h"
#include "host/cli.h"
#include "ionode/io_node.h"
#include "od_export.h"

namespace {

mb2co::cli::Program make_program() {
  namespace cli = mb2co::cli;
  cli::Program p;
  p.name = "mb2co-od";
  p.description =
      "Prints a node's Object Dictionary as Markdown, as an EDS file (CiA 306) or,\n"
      "for the gateway, as its Modbus register map.\n";
  cli::Command c;
  c.options = {
      cli::choice("--node", {"ionode", "gateway"}, "the node (default ionode)"),
      cli::choice("--format", {"md", "eds", "registers"}, "md (default), eds, or registers (gateway only)"),
      cli::choice("--profile", {"linux", "station", "network"},
                  "the gateway image: linux (mb2co-node, default), station (mb2co-gateway.elf),\n"
                  "network (mb2co-gateway-network.elf); an object an image leaves out is absent")};
  p.commands = {c};
  p.footer = "\nexit status: 0 done, 2 usage error (one line on stderr)\n";
  return p;
}

const mb2co::cli::Program& program() {
  static const mb2co::cli::Program p = make_program();
  return p;
}

// Runs the build of `profile` (mb2co-od-<profile> next to this program)
// with the same arguments; returns only when it cannot.
// The EDS's product: the image's name (the linux profile: mb2co-node's OD,
// the EDS of old, docs/mb2co-gateway.eds).
std::string gateway_product(const std::string& profile) {
  return profile == "network" ? "mb2co-gateway-network" : "mb2co-gateway";
}

int run_profile_build(const std::string& profile, char** argv) {
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  std::string path = n > 0 ? std::string(self, static_cast<size_t>(n)) : std::string(argv[0]);
  path = path.substr(0, path.rfind('/') + 1) + "mb2co-od-" + profile;
  execv(path.c_str(), argv);
  std::fprintf(stderr, "mb2co-od: no build of profile %s (%s: not found or not runnable)\n", profile.c_str(),
               path.c_str());
  return mb2co::cli::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  const mb2co::cli::Parsed parsed = mb2co::cli::parse(program(), argc, argv);
  const int early = mb2co::cli::finish_early(program(), parsed, std::cout, std::cerr);
  if (early >= 0) return early;
  const std::string node = parsed.args.get("--node", "ionode");
  const std::string format = parsed.args.get("--format", "md");
  if (format == "registers" && node != "gateway") {
    std::fprintf(stderr, "mb2co-od: --format registers is the gateway's (add --node gateway)\n");
    return mb2co::cli::kExitUsage;
  }
  const std::string profile = parsed.args.get("--profile", "linux");
  if (profile != "linux" && node != "gateway") {
    std::fprintf(stderr, "mb2co-od: --profile is the gateway's (add --node gateway)\n");
    return mb2co::cli::kExitUsage;
  }
  if (profile != mb2co::profile::kName) return run_profile_build(profile, argv);
  const mb2co::CanSink nowhere{[](void*, const mb2co::CanFrame&) { return true; }, nullptr};
  static mb2co::ionode::IoNode io(nowhere);
  static mb2co::gateway::Gateway gw(mb2co::gateway::GatewayPorts{
      nowhere, mb2co::modbus::ByteSink{[](void*, const uint8_t*, uint16_t) { return true; }, nullptr},
      nullptr, 115200});
  const bool is_gw = node == "gateway";
  mb2co::canopen::ObjectDictionary& od = is_gw ? gw.od() : io.od();
  od.restore_defaults(0x0000, 0xFFFF);
  const std::string out =
      format == "registers" ? mb2co::odtool::register_map_markdown(od)
      : format == "md"      ? mb2co::odtool::od_markdown(od, is_gw ? "Object Dictionary: gateway"
                                                                   : "Object Dictionary: CiA 401 I/O test node")
                            : mb2co::odtool::od_eds(od, is_gw ? gateway_product(profile) : "mb2co-ionode");
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

// mb2co-od: prints a node's Object Dictionary as Markdown or as an EDS file.
//   mb2co-od --node ionode --format md|eds
#include <cstdio>
#include <cstring>
#include <string>

#include "gateway/gateway.h"
#include "ionode/io_node.h"
#include "od_export.h"

int main(int argc, char** argv) {
  std::string node = "ionode";
  std::string format = "md";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--node" || a == "--format") && i + 1 < argc) {
      (a == "--node" ? node : format) = argv[++i];
    } else if (a == "--help" || a == "-h") {
      std::printf("usage: mb2co-od [--node ionode|gateway] [--format md|eds|registers]\n");
      return 0;
    } else {
      std::fprintf(stderr, "mb2co-od: unknown argument '%s' (try --help)\n", a.c_str());
      return 2;
    }
  }
  if (node != "ionode" && node != "gateway") {
    std::fprintf(stderr, "mb2co-od: unknown node '%s' (ionode or gateway)\n", node.c_str());
    return 2;
  }
  if (format != "md" && format != "eds" && !(format == "registers" && node == "gateway")) {
    std::fprintf(stderr, "mb2co-od: unknown format '%s' (md, eds; registers for the gateway)\n",
                 format.c_str());
    return 2;
  }
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
                            : mb2co::odtool::od_eds(od, is_gw ? "mb2co-gateway" : "mb2co-ionode");
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

// mb2co-od: prints a node's Object Dictionary as Markdown or as an EDS file.
//   mb2co-od --node ionode --format md|eds
#include <cstdio>
#include <cstring>
#include <string>

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
      std::printf("usage: mb2co-od [--node ionode] [--format md|eds]\n");
      return 0;
    } else {
      std::fprintf(stderr, "mb2co-od: unknown argument '%s' (try --help)\n", a.c_str());
      return 2;
    }
  }
  if (node != "ionode") {
    std::fprintf(stderr, "mb2co-od: unknown node '%s' (known: ionode)\n", node.c_str());
    return 2;
  }
  if (format != "md" && format != "eds") {
    std::fprintf(stderr, "mb2co-od: unknown format '%s' (md or eds)\n", format.c_str());
    return 2;
  }
  mb2co::ionode::IoNode io(mb2co::CanSink{[](void*, const mb2co::CanFrame&) { return true; }, nullptr});
  const std::string out = format == "md"
                              ? mb2co::odtool::od_markdown(io.od(), "Object Dictionary: CiA 401 I/O test node")
                              : mb2co::odtool::od_eds(io.od(), "mb2co-ionode");
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

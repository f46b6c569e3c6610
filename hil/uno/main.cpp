// mb2co-uno: the Uno's gateway image (the very mb2co-gateway.elf that is
// flashed; or the I/O node's, --image ionode) in libsimavr, paced to real
// time, with USART0 on a pty, the
// MCP2515 shield on SocketCAN and the operator panel on stdin/stdout
// (docs/uno-sim.md). The loop is uno_loop.h's; here the options, the
// wiring and the exit status.
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include <iostream>
#include <string>

#include "platform/stop_signal.h"
#include "uno_loop.h"
#include "uno_options.h"
#include "uno_rig.h"

namespace {

using namespace mb2co;

int fail(const std::string& what) {
  fprintf(stderr, "mb2co-uno: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  const cli::Parsed parsed = cli::parse(uno::program(), argc, argv);
  const int early = cli::finish_early(uno::program(), parsed, std::cout, std::cerr);
  if (early >= 0) return early;
  uno::UnoOptions opt;
  uno::apply_options(parsed.args, &opt);
  const uno::UnoImage& image = *uno::find_image(opt.image);  // the parser checked the name
  if (opt.elf.empty()) opt.elf = std::string(MB2CO_UNO_AVR_DIR) + "/" + image.elf;

  const int stop_fd = port::stop_signal_fd();
  if (stop_fd < 0) return fail(std::string("pipe: ") + strerror(errno));
  port::ignore_broken_pipes();

  static uno::UnoRig rig(image);  // large; static like the image's own globals
  uno::UnoWiring wiring(opt);
  const Status opened = wiring.open(opt, rig);
  if (!opened) return fail(opened.message());

  uno::UnoLoop loop(opt, rig, wiring, stop_fd);
  int exit_code = loop.run();
  const Status saved = wiring.close(opt, rig);
  if (!saved && exit_code == 0) exit_code = fail(saved.message());
  loop.report();
  return exit_code;
}

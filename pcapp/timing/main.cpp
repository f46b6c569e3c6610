// mb2co-timing: CAN/CANopen timing analysis from the command line.
#include <iostream>

#include "commands.h"

int main(int argc, char** argv) {
  return mb2co::timing_cli::run(argc, argv, std::cout, std::cerr);
}

// Which function runs which of program()'s commands.
#include <string.h>

#include "commands.h"

namespace mb2co {
namespace master {

CommandFunction command_function(const std::string& name) {
  struct Entry {
    const char* name;
    CommandFunction run;
  };
  static const Entry kCommands[] = {
      {"scan", scan_command},     {"read", read_command},           {"write", write_command},
      {"upload", upload_command}, {"download", download_command},   {"nmt", nmt_command},
      {"sync", sync_command},     {"time", time_command},           {"watch", watch_command},
      {"dump", dump_command},     {"configure", configure_command}, {"serve", serve_command}};
  for (const Entry& e : kCommands) {
    if (name == e.name) return e.run;
  }
  return nullptr;
}

}  // namespace master
}  // namespace mb2co

// read, write, upload, download: SDO transfers to one node or several at
// once (NODE may be a list), typed on the command line or via an EDS.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>

#include "commands.h"
#include "eds_value.h"
#include "exit_codes.h"
#include "part_file.h"
#include "transfer_run.h"
#include "transfer_summary.h"
#include "value_text.h"

namespace mb2co {
namespace master {

namespace {

/// NODE INDEX SUB of a transfer command.
struct Target {
  std::vector<uint8_t> nodes;
  uint16_t index = 0;
  uint8_t sub = 0;
};

/// `w` has at least three words: the commands' min_operands (cli_options.cpp).
Status parse_target(const std::vector<std::string>& w, Target* t) {
  Status s = parse_node_list(w[0], &t->nodes);
  if (!s) return s;
  return parse_index_sub(w[1], w[2], &t->index, &t->sub);
}

/// --block or --segmented (not both), else the transfer's own choice.
Status sdo_mode(const cli::Args& a, canopen::SdoMode* mode) {
  if (a.has("--block") && a.has("--segmented")) return Status::failure("--block or --segmented, not both");
  *mode = a.has("--block")       ? canopen::kSdoBlock
          : a.has("--segmented") ? canopen::kSdoSegmented
                                 : canopen::kSdoAuto;
  return Status::ok();
}

/// Queues one transfer per node and runs them all; the first failure's exit
/// code (each failure printed), kExitOk when all succeeded.
int run_all(const Options& o, Transport& transport, std::vector<std::unique_ptr<Transfer>>& ts,
            std::ostream& err) {
  TransferRun run(o, transport);
  for (auto& t : ts) run.network().queue(t.get());
  if (ts.size() == 1 && !o.json && isatty(STDERR_FILENO) && &err == &std::cerr)
    run.show_progress(ts[0]->node, &err);
  if (!run.run()) return fail(err, kExitInterrupted, "interrupted: transfers aborted (08000000h sent)");
  const Status link = run.network().link_status();
  if (!link) return fail(err, kExitBus, link.message());
  int code = kExitOk;
  for (auto& t : ts) {
    if (t->ok()) continue;
    const int c = exit_code_of(*t);
    fail(err, c, t->failure());
    if (code == kExitOk) code = c;
  }
  return code;
}

/// One transfer of (index, sub) per node of `target`.
std::vector<std::unique_ptr<Transfer>> transfers_for(const Target& target, bool upload, canopen::SdoMode mode,
                                                     const std::vector<uint8_t>& data = {}) {
  std::vector<std::unique_ptr<Transfer>> ts;
  for (uint8_t node : target.nodes) {
    ts.emplace_back(new Transfer);
    Transfer& t = *ts.back();
    t.node = node;
    t.index = target.index;
    t.sub = target.sub;
    t.upload = upload;
    t.mode = mode;
    t.data = data;
  }
  return ts;
}

std::string hex_word(uint32_t v, int digits) {
  char b[16];
  std::snprintf(b, sizeof b, "%0*X", digits, v);
  return b;
}

/// The result line of an upload/download: text or JSON.
void file_result(std::ostream& out, const Transfer& t, const std::string& path, bool json) {
  if (json)
    out << transfer_json(t, path) << "\n";
  else
    out << transfer_summary(t) << (t.upload ? " -> " + path : std::string()) << "\n";
}

}  // namespace

int read_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  const std::vector<std::string>& w = o.args.operands;  // 3 or 4 (the table)
  Target target;
  Status s = parse_target(w, &target);
  if (!s) return fail(err, kExitUsage, "read: " + s.message());
  eds::DataType type;
  s = resolve_type(w.size() == 4 ? w[3] : std::string(), o.eds, target.index, target.sub, &type);
  if (!s) return fail(err, kExitUsage, "read: " + s.message());
  if (const int code = open_transport(o, transport, err)) return code;
  std::vector<std::unique_ptr<Transfer>> ts = transfers_for(target, true, canopen::kSdoAuto);
  int code = run_all(o, transport, ts, err);
  for (auto& t : ts) {
    if (!t->ok()) continue;
    eds::Value v;
    v.bytes = t->data;
    const eds::TypeInfo* info = eds::type_info(static_cast<uint16_t>(type));
    if (info && info->bytes && v.bytes.size() != info->bytes) {
      fail(err, kExitRefused,
           "read: node " + std::to_string(t->node) + " " + hex_word(t->index, 4) + "h/" +
               std::to_string(t->sub) + ": " + std::to_string(v.bytes.size()) + " bytes, not a " +
               info->name + " (" + std::to_string(info->bytes) + " bytes)");
      if (code == kExitOk) code = kExitRefused;
      continue;
    }
    const std::string text = eds::format_value(type, v);
    if (o.json)
      out << "{\"node\":" << unsigned(t->node) << ",\"index\":\"" << hex_word(t->index, 4)
          << "\",\"sub\":" << unsigned(t->sub) << ",\"value\":\"" << text << "\",\"bytes\":" << t->data.size()
          << "}\n";
    else if (ts.size() > 1)
      out << "node " << unsigned(t->node) << ": " << text << "\n";
    else
      out << text << "\n";
  }
  return code;
}

int write_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  const std::vector<std::string>& w = o.args.operands;  // 4 or 5 (the table)
  Target target;
  Status s = parse_target(w, &target);
  if (!s) return fail(err, kExitUsage, "write: " + s.message());
  eds::DataType type;
  s = resolve_type(w.size() == 5 ? w[3] : std::string(), o.eds, target.index, target.sub, &type);
  if (!s) return fail(err, kExitUsage, "write: " + s.message());
  const eds::ValueResult v = eds::parse_value(type, w.back());
  if (!v.value) return fail(err, kExitUsage, "write: " + v.error);
  if (const int code = open_transport(o, transport, err)) return code;
  std::vector<std::unique_ptr<Transfer>> ts = transfers_for(target, false, canopen::kSdoAuto, v.value->bytes);
  const int code = run_all(o, transport, ts, err);
  for (auto& t : ts) {
    if (!t->ok()) continue;
    if (o.json)
      out << "{\"node\":" << unsigned(t->node) << ",\"index\":\"" << hex_word(t->index, 4)
          << "\",\"sub\":" << unsigned(t->sub) << ",\"written\":" << t->data.size() << "}\n";
    else
      out << "node " << unsigned(t->node) << " " << hex_word(t->index, 4) << "h/" << unsigned(t->sub) << ": "
          << t->data.size() << (t->data.size() == 1 ? " byte" : " bytes") << " written\n";
  }
  return code;
}

int upload_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  const std::vector<std::string>& w = o.args.operands;  // exactly 4 (the table)
  canopen::SdoMode mode = canopen::kSdoAuto;
  Status s = sdo_mode(o.args, &mode);
  Target target;
  if (s) s = parse_target(w, &target);
  if (!s) return fail(err, kExitUsage, "upload: " + s.message());
  const uint32_t max_bytes = static_cast<uint32_t>(o.args.uint("--max-bytes", kUploadMaxBytesDefault));
  if (const int code = open_transport(o, transport, err)) return code;
  std::vector<std::unique_ptr<Transfer>> ts = transfers_for(target, true, mode);
  // One file per node when several. The bytes go to PATH.part as they come
  // (the memory stays flat however long the object) and it becomes PATH
  // only when the transfer completed: a file is never half-written.
  std::vector<std::unique_ptr<PartFile>> files;
  for (auto& t : ts) {
    files.emplace_back(new PartFile(target.nodes.size() > 1 ? w[3] + "." + std::to_string(t->node) : w[3]));
    PartFile* file = files.back().get();
    const Status opened = file->open();
    if (!opened) return fail(err, kExitUsage, "upload: " + opened.message());
    t->max_bytes = max_bytes;
    // A file that cannot take the bytes ends the transfer: 08000020h (data
    // cannot be stored) to the node, the file's error to the user.
    t->write = [file](const uint8_t* bytes, size_t n) {
      return file->write(bytes, n) ? canopen::kSdoOk : canopen::kAbortStore;
    };
  }
  int code = run_all(o, transport, ts, err);
  for (size_t i = 0; i < ts.size(); ++i) {
    const Transfer& t = *ts[i];
    PartFile& file = *files[i];
    if (!file.error().empty()) {
      fail(err, kExitUsage, "upload: " + file.error());
      code = kExitUsage;
    }
    if (!t.ok()) {
      file.discard();
      continue;
    }
    const Status committed = file.commit();
    if (!committed) return fail(err, kExitUsage, "upload: " + committed.message());
    file_result(out, t, file.path(), o.json);
  }
  return code;
}

int download_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  const std::vector<std::string>& w = o.args.operands;  // exactly 4 (the table)
  canopen::SdoMode mode = canopen::kSdoAuto;
  Status s = sdo_mode(o.args, &mode);
  Target target;
  if (s) s = parse_target(w, &target);
  if (!s) return fail(err, kExitUsage, "download: " + s.message());
  std::ifstream f(w[3], std::ios::binary);
  if (!f) return fail(err, kExitUsage, "download: cannot read " + w[3]);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (const int code = open_transport(o, transport, err)) return code;
  std::vector<std::unique_ptr<Transfer>> ts = transfers_for(target, false, mode, bytes);
  const int code = run_all(o, transport, ts, err);
  for (auto& t : ts) {
    if (!t->ok()) continue;
    file_result(out, *t, w[3], o.json);
  }
  return code;
}

}  // namespace master
}  // namespace mb2co

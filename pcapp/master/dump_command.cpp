// dump: a node's whole Object Dictionary, as its EDS describes it, uploaded
// and written as a DCF whose ParameterValues are what the node holds. Every
// upload is queued at once on the node's SDO queue (they run one after the
// other on its client). Write-only subs are not asked; subs the node refuses
// are left without ParameterValue and counted. A node-id relative EDS entry
// (e.g. $NODEID+0x180) whose uploaded value is that base plus the node id is
// kept relative, so the DCF also says what makes it so.
#include <cstdio>
#include <deque>
#include <fstream>
#include <sstream>

#include "commands.h"
#include "eds_reader.h"
#include "eds_value.h"
#include "eds_writer.h"
#include "exit_codes.h"
#include "transfer_run.h"

namespace mb2co {
namespace master {

namespace {

std::string hex32(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "%08Xh", v);
  return b;
}

std::string where(uint16_t index, uint8_t sub) {
  char b[24];
  std::snprintf(b, sizeof b, "%04Xh/%u", index, sub);
  return b;
}

/// The uploaded bytes as the sub's value: node-id relative when the EDS
/// default is and the value is its base plus the node id.
eds::Value value_of(const eds::SubObject& s, const std::vector<uint8_t>& bytes, uint8_t node) {
  eds::Value v;
  v.bytes = bytes;
  if (s.default_value && s.default_value->node_id_relative) {
    const auto resolved = eds::resolve(s.type, *s.default_value, node);
    if (resolved && resolved->bytes == bytes) return *s.default_value;
  }
  return v;
}

}  // namespace

int dump_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  const std::vector<std::string>& w = o.args.operands;  // 1 or 2 (the table)
  uint8_t node = 0;
  Status s = parse_node_id(w[0], false, &node);
  if (!s) return fail(err, kExitUsage, "dump: " + s.message());
  if (o.eds.empty())
    return fail(err, kExitUsage, "dump: needs --eds FILE (the node's EDS says which objects to upload)");
  const eds::ParseResult parsed = eds::parse_file(o.eds);
  if (!parsed) return fail(err, kExitUsage, "dump: " + parsed.error.text());
  eds::DeviceDescription model = *parsed.model;

  struct Upload {
    Transfer t;
    eds::SubObject* sub = nullptr;
  };
  std::deque<Upload> uploads;  // a deque: queued Transfers must not move
  unsigned write_only = 0;
  if (const int code = open_transport(o, transport, err)) return code;
  TransferRun run(o, transport);
  for (auto& p : model.objects) {
    for (eds::SubObject& sub : p.second.subs) {
      sub.parameter_value.reset();  // only what the node says goes in
      if (sub.access == eds::AccessType::kWo) {
        ++write_only;
        continue;
      }
      uploads.emplace_back();
      Upload& u = uploads.back();
      u.sub = &sub;
      u.t.node = node;
      u.t.index = p.first;
      u.t.sub = sub.sub;
    }
  }
  // Silence (not a refusal) means the node is not there: the rest would
  // only wait out one SDO timeout each, so everything queued is dropped.
  for (Upload& u : uploads)
    u.t.on_done = [&](Transfer& t) {
      if (!t.ok() && !t.by_server) run.network().abort_all(canopen::kAbortTimeout);
    };
  for (Upload& u : uploads) run.network().queue(&u.t);
  if (!run.run()) return fail(err, kExitInterrupted, "dump: interrupted: transfers aborted (08000000h sent)");
  const Status link = run.network().link_status();
  if (!link) return fail(err, kExitBus, "dump: " + link.message());

  unsigned values = 0;
  std::vector<std::string> refused;
  for (Upload& u : uploads) {
    if (!u.t.ok()) {
      if (!u.t.by_server) return fail(err, exit_code_of(u.t), "dump: " + u.t.failure());
      refused.push_back(where(u.t.index, u.t.sub) + " " + hex32(u.t.result));
      continue;
    }
    const eds::TypeInfo* info = eds::type_info(static_cast<uint16_t>(u.sub->type));
    if (info && info->bytes && u.t.data.size() != info->bytes) {
      refused.push_back(where(u.t.index, u.t.sub) + " " + std::to_string(u.t.data.size()) + " bytes, not " +
                        info->name);
      continue;
    }
    u.sub->parameter_value = value_of(*u.sub, u.t.data, node);
    ++values;
  }

  const std::string dcf = eds::write_dcf(model, node);
  const bool to_file = w.size() == 2;
  if (to_file) {
    const std::string path = w[1];
    const std::string tmp = path + ".part";
    {
      std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
      f << dcf;
      if (!f.good()) return fail(err, kExitUsage, "dump: cannot write " + tmp);
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
      return fail(err, kExitUsage, "dump: cannot write " + path);
  } else {
    out << dcf << std::flush;
  }
  // The summary goes where the DCF does not.
  std::ostream& summary = to_file ? out : err;
  if (o.json) {
    summary << "{\"node\":" << unsigned(node) << ",\"values\":" << values << ",\"write_only\":" << write_only
            << ",\"refused\":[";
    for (size_t i = 0; i < refused.size(); ++i) summary << (i ? "," : "") << "\"" << refused[i] << "\"";
    summary << "]}\n";
  } else {
    summary << "dump: node " << unsigned(node) << ": " << values << " values, " << refused.size()
            << " refused";
    if (!refused.empty()) {
      summary << " (";
      for (size_t i = 0; i < refused.size(); ++i) summary << (i ? ", " : "") << refused[i];
      summary << ")";
    }
    summary << ", " << write_only << " write-only skipped\n";
  }
  return kExitOk;
}

}  // namespace master
}  // namespace mb2co

// mb2co-master dump and configure on vcan0 against three mb2co-node: a
// dump is a DCF pcapp/eds reads back with the node's values; configure
// writes what differs (then reports it equal), saves so that a restarted
// node keeps it, refuses a node of the wrong identity, undoes what it wrote
// on a node that refuses a value halfway, calls a silent node missing and a
// malformed network file an error at its line.
// ctest runs this binary inside hil/uml/run-with-vcan.sh.
#include <gtest/gtest.h>

#include <fstream>

#include "eds_reader.h"
#include "eds_value.h"
#include "eds_writer.h"
#include "master_cli.h"
#include "node_harness.h"

namespace mb2co {
namespace test {
namespace {

const char* const kEds = MB2CO_GATEWAY_EDS;

/// `eeprom_write_us`: the time one EEPROM byte takes (the Uno's: 3300 us).
bool start_node(NodeProcess* node, TempDir* dir, int id, int eeprom_write_us = 0) {
  const std::string n = std::to_string(id);
  return node->start({"--can", "vcan0", "--node-id", n, "--pty", dir->path("st" + n), "--eeprom",
                      dir->path("eeprom" + n), "--eeprom-write-us", std::to_string(eeprom_write_us)});
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << text;
  ASSERT_TRUE(f.good()) << path;
}

/// `read NODE INDEX SUB TYPE` as the master prints it ("" on failure).
std::string read_value(int node, const char* index, int sub, const char* type) {
  const MasterRun run = run_master({"read", std::to_string(node), index, std::to_string(sub), type});
  EXPECT_EQ(run.exit_code, 0) << index << "/" << sub << ": " << run.err;
  return run.out.size() == 1 ? run.out[0] : "";
}

/// The gateway EDS with ParameterValues set (CiA 306 text per index/sub).
struct Setting {
  uint16_t index;
  uint8_t sub;
  const char* value;
};
eds::DeviceDescription configured_model(const std::vector<Setting>& settings) {
  eds::ParseResult eds = eds::parse_file(kEds);
  EXPECT_TRUE(eds) << eds.error.text();
  eds::DeviceDescription m = *eds.model;
  for (const Setting& s : settings) {
    eds::SubObject* sub = nullptr;
    for (eds::SubObject& x : m.objects[s.index].subs)
      if (x.sub == s.sub) sub = &x;
    EXPECT_TRUE(sub) << std::hex << s.index << "/" << unsigned(s.sub);
    if (!sub) continue;
    const eds::ValueResult v = eds::parse_value(sub->type, s.value);
    EXPECT_TRUE(v.value) << v.error;
    sub->parameter_value = v.value;
  }
  return m;
}

/// The line of `run` that starts with "node N:" ("" when none).
std::string node_line(const MasterRun& run, int node) {
  const std::string prefix = "node " + std::to_string(node) + ": ";
  for (const std::string& l : run.out)
    if (l.rfind(prefix, 0) == 0) return l;
  return "";
}

TEST(MasterConfigure, DumpIsADcfWithTheNodesValues) {
  TempDir dir;
  NodeProcess node;
  ASSERT_TRUE(start_node(&node, &dir, 3)) << node.error();
  // A value that is not the EDS default, so the dump must have uploaded it.
  ASSERT_EQ(run_master({"write", "3", "1017", "0", "u16", "1234"}).exit_code, 0);

  const std::string dcf = dir.path("node3.dcf");
  const MasterRun run = run_master({"--eds", kEds, "dump", "3", dcf});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ASSERT_EQ(run.out.size(), 1u) << run.text();
  EXPECT_EQ(run.out[0].rfind("dump: node 3: ", 0), 0u) << run.out[0];
  EXPECT_NE(run.out[0].find(" 0 refused"), std::string::npos) << run.out[0];

  const eds::ParseResult back = eds::parse_file(dcf);
  ASSERT_TRUE(back) << back.error.text();
  const eds::DeviceDescription& m = *back.model;
  ASSERT_TRUE(m.commissioning && m.commissioning->node_id);
  EXPECT_EQ(*m.commissioning->node_id, 3);

  const eds::SubObject* name = m.find(0x1008, 0);
  ASSERT_TRUE(name && name->parameter_value);
  EXPECT_EQ(eds::format_value(name->type, *name->parameter_value), read_value(3, "1008", 0, "vs"));

  const eds::SubObject* heartbeat = m.find(0x1017, 0);
  ASSERT_TRUE(heartbeat && heartbeat->parameter_value);
  EXPECT_EQ(eds::format_value(heartbeat->type, *heartbeat->parameter_value), "0x4D2");  // 1234

  // TPDO1's COB-ID is 180h + node id on the node; the DCF says so.
  const eds::SubObject* cob = m.find(0x1800, 1);
  ASSERT_TRUE(cob && cob->parameter_value);
  EXPECT_TRUE(cob->parameter_value->node_id_relative);
  const auto on_node = eds::resolve(cob->type, *cob->parameter_value, 3);
  ASSERT_TRUE(on_node);
  EXPECT_EQ(eds::format_value(cob->type, *on_node), read_value(3, "1800", 1, "u32"));

  // To stdout: the same DCF; the summary goes to stderr.
  const MasterRun out = run_master({"--eds", kEds, "dump", "3"});
  ASSERT_EQ(out.exit_code, 0) << out.err;
  const eds::ParseResult piped = eds::parse(out.text(), "stdout");
  ASSERT_TRUE(piped) << piped.error.text();
  EXPECT_EQ(piped.model->find(0x1017, 0)->parameter_value, heartbeat->parameter_value);
  EXPECT_NE(out.err.find("dump: node 3: "), std::string::npos) << out.err;

  // Nobody at node id 9: one SDO timeout, not one per object.
  const MasterRun absent = run_master({"-t", "300", "--eds", kEds, "dump", "9", dir.path("x.dcf")});
  EXPECT_EQ(absent.exit_code, 4) << absent.err;
  EXPECT_NE(absent.err.find("node 9 "), std::string::npos) << absent.err;
  EXPECT_NE(absent.err.find("05040000h"), std::string::npos) << absent.err;

  const MasterRun no_eds = run_master({"dump", "3", dir.path("x.dcf")});
  EXPECT_EQ(no_eds.exit_code, 2);
  EXPECT_NE(no_eds.err.find("needs --eds FILE"), std::string::npos) << no_eds.err;
  EXPECT_EQ(no_eds.err.find('\n'), no_eds.err.size() - 1) << "one line";
  EXPECT_FALSE(std::ifstream(dir.path("x.dcf")).good()) << "nothing written";
}

TEST(MasterConfigure, WritesWhatDiffersSavesRefusesAWrongIdentityAndCallsSilenceMissing) {
  TempDir dir;
  NodeProcess nodes[3];
  const int ids[3] = {3, 4, 5};
  // Node 3 programs its EEPROM as slowly as the Uno (3.3 ms per byte: a
  // first save takes ~1.5 s, over the node's loop passes).
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(start_node(&nodes[i], &dir, ids[i], i == 0 ? 3300 : 0)) << nodes[i].error();

  // Heartbeat 250 ms, station debounce 32 ms, TPDO1 event timer 500 ms,
  // TPDO1 COB-ID and mapping count (the node refuses both while TPDO1 is
  // valid: only the CiA 301 order gets them in), and the (const) device
  // name, which configure must leave alone. The DCF lists the mapping after
  // the COB-ID, as objects are sorted: the order is configure's doing.
  const std::vector<Setting> settings = {{0x1017, 0, "250"}, {0x2000, 6, "0x20"},
                                         {0x1800, 5, "500"}, {0x1800, 1, "$NODEID+0x190"},
                                         {0x1A00, 0, "1"},   {0x1008, 0, "other name"}};
  write_file(dir.path("good.dcf"), eds::write_dcf(configured_model(settings), 3));
  // Node 5's DCF wants another product than the node has.
  const std::string product = read_value(5, "1018", 2, "u32");
  ASSERT_FALSE(product.empty());
  const uint32_t other = static_cast<uint32_t>(std::stoul(product, nullptr, 16)) + 1;
  std::vector<Setting> wrong = settings;
  const std::string other_text = "0x" + [&] {
    char b[16];
    std::snprintf(b, sizeof b, "%X", other);
    return std::string(b);
  }();
  wrong.push_back({0x1018, 2, other_text.c_str()});
  write_file(dir.path("wrong.dcf"), eds::write_dcf(configured_model(wrong), 5));
  write_file(dir.path("net.cpj"),
             "[Topology]\nNetName=test\nNodes=3\n"
             "Node3Present=1\nNode3Name=first\nNode3DCFName=good.dcf\n"
             "Node4Present=0x01\nNode4DCFName=good.dcf\n"
             "Node5Present=1\nNode5DCFName=wrong.dcf\n");

  const MasterRun first = run_master({"configure", dir.path("net.cpj"), "--save"});
  EXPECT_EQ(first.exit_code, 1) << first.text() << first.err;
  EXPECT_EQ(node_line(first, 3),
            "node 3: configured: 5 written, 0 equal, 1 read-only skipped, saved, started");
  EXPECT_EQ(node_line(first, 4),
            "node 4: configured: 5 written, 0 equal, 1 read-only skipped, saved, started");
  char want[96];
  std::snprintf(want, sizeof want, "node 5: refused: wrong identity: product 0x%08X want 0x%08X",
                static_cast<unsigned>(other - 1), static_cast<unsigned>(other));
  EXPECT_EQ(node_line(first, 5), want);

  // "saved" means stored: node 3, killed (no clean exit that would finish
  // a save) right after configure returned, starts with the values.
  nodes[0].stop(9);
  NodeProcess restarted;
  ASSERT_TRUE(start_node(&restarted, &dir, 3)) << restarted.error();

  for (int node : {3, 4}) {
    EXPECT_EQ(read_value(node, "1017", 0, "u16"), "0xFA");
    EXPECT_EQ(read_value(node, "2000", 6, "u16"), "0x20");
    EXPECT_EQ(read_value(node, "1800", 5, "u16"), "0x1F4");
    EXPECT_EQ(read_value(node, "1800", 1, "u32"), node == 3 ? "0x193" : "0x194") << "valid again";
    EXPECT_EQ(read_value(node, "1A00", 0, "u8"), "0x1");
    EXPECT_NE(read_value(node, "1008", 0, "vs"), "other name");
  }
  EXPECT_EQ(read_value(5, "1017", 0, "u16"), "0x64") << "a refused node is left as it was";

  // Again: nothing to write. JSON says the same.
  write_file(dir.path("two.cpj"),
             "[Topology]\nNodes=2\nNode3Present=1\nNode3DCFName=good.dcf\n"
             "Node4Present=1\nNode4DCFName=good.dcf\n");
  const MasterRun second = run_master({"--json", "configure", dir.path("two.cpj"), "--no-start"});
  EXPECT_EQ(second.exit_code, 0) << second.err;
  ASSERT_EQ(second.out.size(), 2u) << second.text();
  EXPECT_EQ(second.out[0],
            "{\"node\":3,\"result\":\"configured\",\"written\":0,\"equal\":5,\"read_only\":1,"
            "\"saved\":false,\"started\":false}");

  // Saved: node 3 restarted with its EEPROM file keeps the values.
  EXPECT_EQ(restarted.stop(), 0);
  NodeProcess again;
  ASSERT_TRUE(start_node(&again, &dir, 3)) << again.error();
  EXPECT_EQ(read_value(3, "1017", 0, "u16"), "0xFA");
  EXPECT_EQ(read_value(3, "2000", 6, "u16"), "0x20");
  EXPECT_EQ(read_value(3, "1800", 5, "u16"), "0x1F4");
  EXPECT_EQ(read_value(3, "1800", 1, "u32"), "0x193");
  EXPECT_EQ(read_value(3, "1A00", 0, "u8"), "0x1");

  // A node id nobody answers for: missing, exit 4; the others still done.
  write_file(dir.path("absent.cpj"),
             "[Topology]\nNodes=2\nNode3Present=1\nNode3DCFName=good.dcf\n"
             "Node9Present=1\nNode9DCFName=good.dcf\n");
  const MasterRun absent = run_master({"-t", "300", "configure", dir.path("absent.cpj")});
  EXPECT_EQ(absent.exit_code, 4) << absent.err;
  EXPECT_EQ(node_line(absent, 3), "node 3: configured: 0 written, 5 equal, 1 read-only skipped, started");
  EXPECT_EQ(node_line(absent, 9), "node 9: missing (no answer to 1018h/1)");
}

/// Every (index, sub) of `settings` as the node holds it now.
std::vector<std::string> read_all(int node, const std::vector<Setting>& settings) {
  std::vector<std::string> values;
  for (const Setting& s : settings) {
    char index[8];
    std::snprintf(index, sizeof index, "%04X", s.index);
    const MasterRun run =
        run_master({"--eds", kEds, "read", std::to_string(node), index, std::to_string(s.sub)});
    values.push_back(run.exit_code == 0 && run.out.size() == 1 ? run.out[0] : "error: " + run.err);
  }
  return values;
}

TEST(MasterConfigure, AValueRefusedHalfwayLeavesTheNodeAsItWas) {
  TempDir dir;
  NodeProcess nodes[2];
  for (int i = 0; i < 2; ++i) ASSERT_TRUE(start_node(&nodes[i], &dir, 3 + i)) << nodes[i].error();

  // Node 3: two station settings, then a debounce above its limit (1..500).
  const std::vector<Setting> station = {{0x1017, 0, "250"}, {0x2000, 3, "0"}, {0x2000, 6, "600"}};
  // Node 4: a heartbeat, then TPDO1 remapped onto 1017h, which is not
  // PDO-mappable: refused in the middle of the PDO order (TPDO1 already
  // invalid, its event timer and mapping count already written).
  const std::vector<Setting> pdo = {
      {0x1017, 0, "300"}, {0x1800, 5, "700"}, {0x1A00, 0, "1"}, {0x1A00, 1, "0x10170010"}};
  // What the restore has to bring back, read before (with what the PDO
  // order touches beside the DCF's own entries).
  std::vector<Setting> pdo_read = pdo;
  pdo_read.push_back({0x1800, 1, ""});
  pdo_read.push_back({0x1A00, 2, ""});
  const std::vector<std::string> before3 = read_all(3, station), before4 = read_all(4, pdo_read);
  // A DCF from an EDS that gave no limit (as an older one): only the node
  // can refuse the value, after the two before it are written.
  eds::DeviceDescription unlimited = configured_model(station);
  for (eds::SubObject& sub : unlimited.objects[0x2000].subs) sub.high_limit.reset();
  write_file(dir.path("station.dcf"), eds::write_dcf(unlimited, 3));
  write_file(dir.path("pdo.dcf"), eds::write_dcf(configured_model(pdo), 4));
  write_file(dir.path("net.cpj"),
             "[Topology]\nNodes=2\nNode3Present=1\nNode3DCFName=station.dcf\n"
             "Node4Present=1\nNode4DCFName=pdo.dcf\n");

  const MasterRun run = run_master({"configure", dir.path("net.cpj")});
  EXPECT_EQ(run.exit_code, 1) << run.text() << run.err;
  const std::vector<std::string> want = {
      "node 3: refused: writing 2000h/6: SDO abort 06090031h (value of parameter written too high)",
      "node 3: restored 2000h/3 = 0x1",
      "node 3: restored 1017h/0 = 0x64",
      "node 4: refused: writing 1A00h/1: SDO abort 06040041h (object cannot be mapped to the PDO)",
      "node 4: restored 1A00h/0 = 0x2",
      "node 4: restored 1800h/5 = 0x64",
      "node 4: restored 1800h/1 = 0x184",
      "node 4: restored 1017h/0 = 0x64",
  };
  EXPECT_EQ(run.out, want) << run.text();
  EXPECT_EQ(read_all(3, station), before3);
  EXPECT_EQ(read_all(4, pdo_read), before4);
  EXPECT_EQ(nodes[0].stop(), 0);
  EXPECT_EQ(nodes[1].stop(), 0);
}

TEST(MasterConfigure, BrokenNetworkFilesAreRefusedAtTheirLine) {
  TempDir dir;
  struct Case {
    const char* text;
    const char* says;
  } const cases[] = {
      {"[Topology]\nNodes=1\nNode3Present\n", "net.cpj:3: want KEY=VALUE"},
      {"[Topology]\nNodes=1\nNode130Present=1\n", "net.cpj:3: node id in 'Node130Present' is not 1..127"},
      {"[Topology]\nNodes=2\nNode3Present=1\nNode3DCFName=a.dcf\n", "net.cpj:2: Nodes=2 but 1 nodes"},
      {"; no topology\n[Other]\nA=1\n", "net.cpj:3: no [Topology] section"},
      {"[Topology]\nNodes=1\nNode3Present=1\n", "net.cpj:3: node 3 is present but has no Node3DCFName"},
      {"[Topology]\nNodes=1\nNode3Present=1\nNode3DCFName=nosuch.dcf\n", "nosuch.dcf: cannot read"},
  };
  for (const Case& c : cases) {
    write_file(dir.path("net.cpj"), c.text);
    const MasterRun run = run_master({"configure", dir.path("net.cpj")});
    EXPECT_EQ(run.exit_code, 2) << c.text;
    EXPECT_NE(run.err.find(c.says), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << "one line: " << run.err;
    EXPECT_TRUE(run.out.empty());
  }
}

}  // namespace
}  // namespace test
}  // namespace mb2co

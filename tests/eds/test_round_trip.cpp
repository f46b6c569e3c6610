// Round trips: the docs EDS files read back as the OD tables they were
// generated from (every row: index, sub, name, data type, access, PDO
// mapping, default with $NODEID), and write -> read gives the same model,
// for the docs files as DCFs and for a model with every data type.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "canopen/od.h"
#include "eds_reader.h"
#include "eds_value.h"
#include "eds_writer.h"
#include "gateway/gateway.h"
#include "ionode/io_node.h"

using namespace mb2co::eds;
namespace co = mb2co::canopen;
using Bytes = std::vector<uint8_t>;

namespace {

const mb2co::CanSink kNowhere{[](void*, const mb2co::CanFrame&) { return true; }, nullptr};

co::ObjectDictionary& ionode_od() {
  static mb2co::ionode::IoNode io(kNowhere);
  return io.od();
}

co::ObjectDictionary& gateway_od() {
  static mb2co::gateway::Gateway gw(mb2co::gateway::GatewayPorts{
      kNowhere, mb2co::modbus::ByteSink{[](void*, const uint8_t*, uint16_t) { return true; }, nullptr},
      nullptr, 115200});
  return gw.od();
}

DeviceDescription read_doc(const char* file) {
  const ParseResult r = parse_file(std::string(MB2CO_DOCS_DIR) + "/" + file);
  EXPECT_TRUE(r) << r.error.text();
  return r.model.value_or(DeviceDescription{});
}

/// CiA 306 tools show a record's subs under the record: a sub carries its own
/// name (the OD's flat name less "<record>: "), sub 0 CiA 301's name.
std::string expected_name(const co::ObjectDictionary& od, uint16_t row, bool in_record) {
  const std::string flat = od.definition().names[row];
  if (!in_record) return flat;
  if (od.entry(row).sub == 0) return "Highest sub-index supported";
  const size_t colon = flat.find(": ");
  return colon == std::string::npos ? flat : flat.substr(colon + 2);
}

const co::OdLimit* limit_of(const co::ObjectDictionary& od, uint16_t index, uint8_t sub) {
  for (uint8_t i = 0; i < od.definition().limit_count; ++i) {
    const co::OdLimit& l = od.definition().limits[i];
    if (l.index == index && l.sub == sub) return &l;
  }
  return nullptr;
}

Bytes little_endian(uint64_t v, size_t n) {
  Bytes b(n);
  for (size_t i = 0; i < n; ++i) b[i] = static_cast<uint8_t>(v >> (8 * i));
  return b;
}

/// A limit's bytes as the EDS holds them: a REAL's IEEE bits (the OD holds
/// its ordered key), an integer as it is.
Bytes limit_bytes(co::OdLimitValue v, DataType type) {
  const size_t n = type_info(type).bytes;
  if (type_info(type).kind == ValueKind::kReal) {
    return little_endian(co::od_real_limit_bits(v, static_cast<uint8_t>(n)), n);
  }
  return little_endian(static_cast<uint64_t>(v), n);
}

AccessType expected_access(uint8_t attr) {
  if (attr & co::kAttrConst) return AccessType::kConst;
  const bool r = attr & co::kAttrRead, w = attr & co::kAttrWrite;
  return r && w ? AccessType::kRw : w ? AccessType::kWo : AccessType::kRo;
}

/// Every row of `od` is in `m` as the generator describes it, and `m` has
/// nothing else.
void expect_model_is_od(const DeviceDescription& m, const co::ObjectDictionary& od) {
  size_t subs_in_model = 0;
  for (const auto& o : m.objects) subs_in_model += o.second.subs.size();
  EXPECT_EQ(subs_in_model, od.row_count());
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const co::OdEntry e = od.entry(r);
    SCOPED_TRACE(::testing::Message() << std::hex << e.index << "/" << int{e.sub});
    const Object* o = m.find(e.index);
    const SubObject* s = m.find(e.index, e.sub);
    ASSERT_NE(s, nullptr);
    const bool single =
        od.first_row(e.index) == r && (r + 1 == od.row_count() || od.index_of(r + 1) != e.index);
    EXPECT_EQ(o->type, single && e.sub == 0 ? ObjectType::kVar : ObjectType::kRecord);
    EXPECT_EQ(s->name, expected_name(od, r, o->type == ObjectType::kRecord));
    EXPECT_EQ(static_cast<uint16_t>(s->type), e.data_type());
    EXPECT_EQ(s->access, expected_access(e.attr));
    EXPECT_EQ(s->pdo_mapping, (e.attr & co::kAttrPdo) != 0);
    ASSERT_TRUE(s->default_value);
    if (e.attr & co::kAttrString) {
      const char* text = od.definition().strings + (e.def & 0xFFFF);
      EXPECT_EQ(s->default_value->bytes, Bytes(text, text + std::strlen(text)));
      EXPECT_FALSE(s->default_value->node_id_relative);
    } else {
      Bytes def(type_info(s->type).bytes);
      for (size_t i = 0; i < def.size() && i < 4; ++i) def[i] = static_cast<uint8_t>(e.def >> (8 * i));
      EXPECT_EQ(s->default_value->bytes, def);
      EXPECT_EQ(s->default_value->node_id_relative, (e.attr & co::kAttrNodeId) != 0);
    }
    EXPECT_FALSE(s->parameter_value);
    // LowLimit/HighLimit exactly where the node enforces limits beyond the type.
    const co::OdLimit* lim = limit_of(od, e.index, e.sub);
    ASSERT_EQ(s->low_limit.has_value(), lim != nullptr);
    ASSERT_EQ(s->high_limit.has_value(), lim != nullptr);
    if (lim != nullptr) {
      EXPECT_EQ(s->low_limit->bytes, limit_bytes(lim->min, s->type));
      EXPECT_EQ(s->high_limit->bytes, limit_bytes(lim->max, s->type));
    }
  }
  // Every object is in one of the three object lists (data types too).
  for (const auto& o : m.objects) {
    const uint16_t i = o.first;
    const auto lists = std::count(m.mandatory_objects.begin(), m.mandatory_objects.end(), i) +
                       std::count(m.optional_objects.begin(), m.optional_objects.end(), i) +
                       std::count(m.manufacturer_objects.begin(), m.manufacturer_objects.end(), i);
    EXPECT_EQ(lists, 1) << std::hex << i;
  }
  // [DeviceInfo] numbers are 1018h's (a library reading only the EDS shows them).
  const struct {
    const char* key;
    uint8_t sub;
  } numbers[] = {{"VendorNumber", 1}, {"ProductNumber", 2}, {"RevisionNumber", 3}};
  for (const auto& n : numbers) {
    const auto kv =
        std::find_if(m.device_info.begin(), m.device_info.end(),
                     [&](const std::pair<std::string, std::string>& p) { return p.first == n.key; });
    ASSERT_NE(kv, m.device_info.end()) << n.key;
    const std::optional<uint64_t> v = parse_unsigned(kv->second, UINT32_MAX);
    ASSERT_TRUE(v) << kv->second;
    EXPECT_EQ(*v, od.entry(od.find(0x1018, n.sub)).def) << n.key;
  }
}

}  // namespace

TEST(EdsRoundTrip, IonodeEdsReadsBackAsItsOd) {
  expect_model_is_od(read_doc("mb2co-ionode.eds"), ionode_od());
}

TEST(EdsRoundTrip, GatewayEdsReadsBackAsItsOd) {
  expect_model_is_od(read_doc("mb2co-gateway.eds"), gateway_od());
}

TEST(EdsRoundTrip, DocsEdsAsDcfReadsBackEqualAndEvaluatesNodeId) {
  for (const char* file : {"mb2co-ionode.eds", "mb2co-gateway.eds"}) {
    SCOPED_TRACE(file);
    const DeviceDescription m = read_doc(file);
    EXPECT_EQ(parse(write_eds(m), "eds").model, m);
    const std::string dcf = write_dcf(m, 0x22, 250);
    const ParseResult back = parse(dcf, "dcf");
    ASSERT_TRUE(back) << back.error.text();
    EXPECT_EQ(*back.model, with_commissioning(m, 0x22, 250));
    EXPECT_EQ(back.model->commissioning->node_id, 0x22);
    // The same DCF read for node 0x22: TPDO1's COB-ID is 180h + 22h.
    const ParseResult evaluated = parse(dcf, "dcf", 0x22);
    ASSERT_TRUE(evaluated) << evaluated.error.text();
    EXPECT_EQ(evaluated.model->find(0x1800, 1)->default_value, (Value{{0xA2, 0x01, 0, 0}, false}));
  }
}

TEST(EdsRoundTrip, ModelWithEveryDataTypeWritesAndReadsBackEqual) {
  DeviceDescription m;
  m.file_info = {{"FileName", "all.dcf"}, {"EDSVersion", "4.0"}};
  m.device_info = {{"VendorName", "mb2co"}, {"ProductName", "every type"}};
  m.other_sections.push_back(OtherSection{"Comments", {{"Lines", "1"}, {"Line1", "all types"}}});
  Object dev{0x1000, "Device type", ObjectType::kVar, std::nullopt, {}};
  dev.subs.push_back(SubObject{0, "Device type", DataType::kUnsigned32, AccessType::kRo, false,
                               Value{{0x91, 1, 3, 0}, false}, std::nullopt, std::nullopt, std::nullopt, ""});
  m.objects[0x1000] = dev;
  m.mandatory_objects = {0x1000};
  // One VAR per type with a default and a different configured value, and a
  // RECORD whose subs hold each type's extremes.
  Object rec{0x3000, "Extremes", ObjectType::kRecord, 0x1u, {}};
  uint16_t index = 0x2000;
  uint8_t sub = 0;
  rec.subs.push_back(SubObject{sub++, "Highest sub-index", DataType::kUnsigned8, AccessType::kConst, false,
                               std::nullopt, std::nullopt, std::nullopt, std::nullopt, ""});
  for (const TypeInfo& t : all_types()) {
    SCOPED_TRACE(t.name);
    const auto value = [&](const char* text) {
      const ValueResult v = parse_value(t.type, text);
      EXPECT_TRUE(v.value) << text << ": " << v.error;
      return v.value;
    };
    const bool integer = t.kind == ValueKind::kSigned || t.kind == ValueKind::kUnsigned;
    SubObject s{
        0, t.name, t.type, AccessType::kRw, integer, std::nullopt, std::nullopt, std::nullopt, std::nullopt,
        ""};
    switch (t.kind) {
      case ValueKind::kBoolean:
        s.default_value = value("1");
        s.parameter_value = value("0");
        break;
      case ValueKind::kSigned:
        s.default_value = value("-1");
        s.parameter_value = value("$NODEID");
        s.low_limit = value("-100");
        s.high_limit = value("100");
        break;
      case ValueKind::kUnsigned:
        s.default_value = value("$NODEID+0x80");
        s.parameter_value = value("0x81");
        s.low_limit = value("1");
        break;
      case ValueKind::kReal:
        s.default_value = value("0.1");
        s.parameter_value = value("-1.25e-7");
        s.high_limit = value("1000.5");
        break;
      case ValueKind::kVisibleString:
        s.default_value = value("mb2co = gateway; [v1]");
        s.parameter_value = value("");
        s.denotation = "label";
        break;
      case ValueKind::kHexBytes:
        s.default_value = value("0041FF00");
        s.parameter_value = value("");
        break;
    }
    Object var{index,
               t.name,
               t.type == DataType::kDomain ? ObjectType::kDomain : ObjectType::kVar,
               std::nullopt,
               {s}};
    m.objects[index] = var;
    m.manufacturer_objects.push_back(index++);
    SubObject extreme{sub++,        std::string(t.name) + " extreme",
                      t.type,       AccessType::kRo,
                      false,        std::nullopt,
                      std::nullopt, std::nullopt,
                      std::nullopt, ""};
    if (t.kind == ValueKind::kSigned) {
      extreme.default_value = Value{Bytes(t.bytes, 0), false};
      extreme.default_value->bytes.back() = 0x80;  // the type's minimum
    } else if (t.kind == ValueKind::kUnsigned) {
      extreme.default_value = Value{Bytes(t.bytes, 0xFF), false};  // the maximum
    } else if (t.kind == ValueKind::kReal) {
      extreme.default_value = Value{Bytes(t.bytes, 0), false};
      extreme.default_value->bytes[0] = 1;  // the smallest subnormal
    } else if (t.kind == ValueKind::kBoolean) {
      extreme.default_value = Value{{1}, false};
    }
    rec.subs.push_back(extreme);
  }
  rec.subs[0].default_value = Value{{static_cast<uint8_t>(sub - 1)}, false};
  m.objects[0x3000] = rec;
  m.manufacturer_objects.push_back(0x3000);

  const std::string text = write_dcf(m, 5, 500);
  const ParseResult back = parse(text, "all.dcf");
  ASSERT_TRUE(back) << back.error.text() << "\n" << text;
  EXPECT_EQ(*back.model, with_commissioning(m, 5, 500)) << text;
  EXPECT_EQ(parse(write_eds(m), "all.eds").model, m);
}

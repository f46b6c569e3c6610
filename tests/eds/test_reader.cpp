// eds::parse: what each CiA 306 feature becomes in the model (black box).
// Malformed files are in test_bad_corpus.cpp.
#include <gtest/gtest.h>

#include "eds_reader.h"

using namespace mb2co::eds;
using Bytes = std::vector<uint8_t>;

namespace {

const std::string kHead =
    "[FileInfo]\nFileName=t.eds\nEDSVersion=4.0\n\n[DeviceInfo]\nVendorName=mb2co\nNrOfRXPDO=0\n\n"
    "[MandatoryObjects]\nSupportedObjects=1\n1=0x1000\n\n"
    "[1000]\nParameterName=Device type\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\n"
    "DefaultValue=0x00030191\nPDOMapping=0\n\n";

DeviceDescription parse_ok(const std::string& text, std::optional<uint8_t> node = std::nullopt) {
  const ParseResult r = parse(text, "t.eds", node);
  EXPECT_TRUE(r) << r.error.text();
  return r.model.value_or(DeviceDescription{});
}

std::string parse_error(const std::string& text) {
  const ParseResult r = parse(text, "t.eds");
  EXPECT_FALSE(r) << "accepted";
  return r.error.text();
}

}  // namespace

TEST(EdsReader, MinimalFileGivesInfoListsAndAVar) {
  const DeviceDescription m = parse_ok(kHead);
  EXPECT_EQ(m.file_info, (KeyValues{{"FileName", "t.eds"}, {"EDSVersion", "4.0"}}));
  EXPECT_EQ(*find_key(m.device_info, "vendorname"), "mb2co");
  EXPECT_EQ(m.mandatory_objects, std::vector<uint16_t>{0x1000});
  EXPECT_TRUE(m.optional_objects.empty());
  EXPECT_FALSE(m.commissioning);
  const Object* o = m.find(0x1000);
  ASSERT_NE(o, nullptr);
  EXPECT_EQ(o->type, ObjectType::kVar);
  EXPECT_EQ(o->name, "Device type");
  ASSERT_EQ(o->subs.size(), 1u);
  const SubObject& s = o->subs[0];
  EXPECT_EQ(s.sub, 0);
  EXPECT_EQ(s.name, "Device type");
  EXPECT_EQ(s.type, DataType::kUnsigned32);
  EXPECT_EQ(s.access, AccessType::kRo);
  EXPECT_FALSE(s.pdo_mapping);
  EXPECT_EQ(s.default_value, (Value{{0x91, 0x01, 0x03, 0x00}, false}));
  EXPECT_FALSE(s.parameter_value);
}

TEST(EdsReader, RecordSubsAreSortedBySubIndexWhateverTheFileOrder) {
  const DeviceDescription m =
      parse_ok(kHead +
               "[OptionalObjects]\nSupportedObjects=1\n1=0x1018\n"
               "[1018]\nParameterName=Identity\nObjectType=0x9\nSubNumber=2\n"
               "[1018sub1]\nParameterName=Vendor\nObjectType=0x7\nDataType=0x0007\n"
               "AccessType=ro\nDefaultValue=0xB2C\n"
               "[1018Sub0]\nParameterName=Highest\nDataType=0x0005\nAccessType=const\n"
               "DefaultValue=1\n");
  const Object* o = m.find(0x1018);
  ASSERT_NE(o, nullptr);
  EXPECT_EQ(o->type, ObjectType::kRecord);
  ASSERT_EQ(o->subs.size(), 2u);
  EXPECT_EQ(o->subs[0].name, "Highest");
  EXPECT_EQ(o->subs[0].access, AccessType::kConst);
  EXPECT_EQ(o->subs[1].sub, 1);
  EXPECT_EQ(o->subs[1].default_value->bytes, (Bytes{0x2C, 0x0B, 0, 0}));
  EXPECT_EQ(m.optional_objects, std::vector<uint16_t>{0x1018});
}

TEST(EdsReader, SubSectionNumbersAreHex) {
  const DeviceDescription m = parse_ok(kHead +
                                       "[ManufacturerObjects]\nSupportedObjects=1\n1=0x2000\n"
                                       "[2000]\nParameterName=Table\nObjectType=0x8\nSubNumber=2\n"
                                       "[2000sub0]\nParameterName=n\nDataType=0x0005\nAccessType=ro\n"
                                       "[2000sub1A]\nParameterName=x\nDataType=0x0005\nAccessType=rw\n");
  EXPECT_NE(m.find(0x2000, 0x1A), nullptr);
  EXPECT_EQ(m.find(0x2000)->type, ObjectType::kArray);
}

TEST(EdsReader, CompactSubObjIsExpandedWithNamesValuesAndDenotations) {
  const DeviceDescription m = parse_ok(kHead +
                                       "[ManufacturerObjects]\nSupportedObjects=1\n1=0x2100\n"
                                       "[2100]\nParameterName=Outputs\nObjectType=0x8\nCompactSubObj=3\n"
                                       "DataType=0x0006\nAccessType=rww\nPDOMapping=1\nDefaultValue=0x10\n"
                                       "LowLimit=1\nHighLimit=100\n"
                                       "[2100Name]\nNrOfEntries=1\n2=Middle output\n"
                                       "[2100Value]\nNrOfEntries=2\n1=5\n3=0x63\n"
                                       "[2100Denotation]\nNrOfEntries=1\n1=Pump\n");
  const Object* o = m.find(0x2100);
  ASSERT_NE(o, nullptr);
  ASSERT_EQ(o->subs.size(), 4u);
  EXPECT_EQ(o->subs[0].name, "NrOfObjects");
  EXPECT_EQ(o->subs[0].type, DataType::kUnsigned8);
  EXPECT_EQ(o->subs[0].access, AccessType::kRo);
  EXPECT_EQ(o->subs[0].default_value, (Value{{3}, false}));
  for (uint8_t k = 1; k <= 3; ++k) {
    const SubObject& s = o->subs[k];
    EXPECT_EQ(s.sub, k);
    EXPECT_EQ(s.type, DataType::kUnsigned16);
    EXPECT_EQ(s.access, AccessType::kRww);
    EXPECT_TRUE(s.pdo_mapping);
    EXPECT_EQ(s.default_value->bytes, (Bytes{0x10, 0}));
    EXPECT_EQ(s.low_limit->bytes, (Bytes{1, 0}));
  }
  EXPECT_EQ(o->subs[1].name, "Outputs1");
  EXPECT_EQ(o->subs[2].name, "Middle output");
  EXPECT_EQ(o->subs[1].parameter_value->bytes, (Bytes{5, 0}));
  EXPECT_FALSE(o->subs[2].parameter_value);
  EXPECT_EQ(o->subs[3].parameter_value->bytes, (Bytes{0x63, 0}));
  EXPECT_EQ(o->subs[1].denotation, "Pump");
}

TEST(EdsReader, IniSyntaxCrLfCommentsBlanksAndCase) {
  const DeviceDescription m = parse_ok(
      "; a comment\r\n[fileinfo]\r\n  FileName = t.eds  \r\n\r\n[DEVICEINFO]\r\nVendorName=x\r\n"
      "[mandatoryobjects]\r\nsupportedobjects=1\r\n1=4096\r\n[1000]\r\n\tparametername=Device type\r\n"
      "datatype=7\r\naccesstype=RO\r\n");
  EXPECT_EQ(m.file_info, (KeyValues{{"FileName", "t.eds"}}));
  ASSERT_NE(m.find(0x1000, 0), nullptr);
  EXPECT_EQ(m.find(0x1000)->type, ObjectType::kVar);  // no ObjectType: VAR
  EXPECT_EQ(m.find(0x1000, 0)->access, AccessType::kRo);
  EXPECT_FALSE(m.find(0x1000, 0)->default_value);
}

TEST(EdsReader, DomainObjectDefaultsToDomainTypeReadWrite) {
  const DeviceDescription m = parse_ok(kHead +
                                       "[ManufacturerObjects]\nSupportedObjects=1\n1=0x2F00\n"
                                       "[2F00]\nParameterName=Program\nObjectType=0x2\nDefaultValue=CAFE\n");
  const SubObject* s = m.find(0x2F00, 0);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(m.find(0x2F00)->type, ObjectType::kDomain);
  EXPECT_EQ(s->type, DataType::kDomain);
  EXPECT_EQ(s->access, AccessType::kRw);
  EXPECT_EQ(s->default_value->bytes, (Bytes{0xCA, 0xFE}));
}

TEST(EdsReader, NodeIdRelativeValuesSymbolicOrEvaluated) {
  const std::string text = kHead +
                           "[OptionalObjects]\nSupportedObjects=1\n1=0x1800\n"
                           "[1800]\nParameterName=TPDO1\nObjectType=0x9\nSubNumber=1\n"
                           "[1800sub1]\nParameterName=COB-ID\nDataType=0x0007\nAccessType=rw\n"
                           "DefaultValue=$NODEID+0x180\nParameterValue=0x180+$NODEID\n";
  const DeviceDescription m = parse_ok(text);
  const SubObject* sym = m.find(0x1800, 1);
  ASSERT_NE(sym, nullptr);
  EXPECT_EQ(sym->default_value, (Value{{0x80, 0x01, 0, 0}, true}));
  EXPECT_EQ(sym->parameter_value, sym->default_value);
  const DeviceDescription m7 = parse_ok(text, 7);
  EXPECT_EQ(m7.find(0x1800, 1)->default_value, (Value{{0x87, 0x01, 0, 0}, false}));
  EXPECT_EQ(m7.find(0x1800, 1)->parameter_value, (Value{{0x87, 0x01, 0, 0}, false}));
  const ParseResult bad = parse(text, "t.eds", 0);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error.text(), "t.eds: node id 0 is not 1..127");
}

TEST(EdsReader, LimitsFlagsAndEmptyNumericDefault) {
  const DeviceDescription m = parse_ok(kHead +
                                       "[ManufacturerObjects]\nSupportedObjects=1\n1=0x2001\n"
                                       "[2001]\nParameterName=Speed\nObjFlags=0x3\nDataType=0x0003\n"
                                       "AccessType=rw\nLowLimit=-100\nHighLimit=100\nDefaultValue=\n");
  const Object* o = m.find(0x2001);
  ASSERT_NE(o, nullptr);
  EXPECT_EQ(o->obj_flags, 3u);
  EXPECT_EQ(o->subs[0].low_limit->bytes, (Bytes{0x9C, 0xFF}));
  EXPECT_EQ(o->subs[0].high_limit->bytes, (Bytes{100, 0}));
  EXPECT_FALSE(o->subs[0].default_value);  // "DefaultValue=" on a number: none given
}

TEST(EdsReader, CommissioningAndOtherSectionsAreKept) {
  const DeviceDescription m = parse_ok(kHead +
                                       "[Comments]\nLines=1\nLine1=hello\n"
                                       "[DeviceComissioning]\nNodeID=0x22\nNodeName=Pump\nBaudrate=250\n");
  ASSERT_TRUE(m.commissioning);
  EXPECT_EQ(m.commissioning->node_id, 0x22);
  EXPECT_EQ(m.commissioning->baudrate_kbit, 250);
  EXPECT_EQ(m.commissioning->others, (KeyValues{{"NodeName", "Pump"}}));
  ASSERT_EQ(m.other_sections.size(), 1u);
  EXPECT_EQ(m.other_sections[0].name, "Comments");
  EXPECT_EQ(m.other_sections[0].entries, (KeyValues{{"Lines", "1"}, {"Line1", "hello"}}));
}

TEST(EdsReader, DataTypeEntriesBelow1000hNeedNoList) {
  const DeviceDescription m = parse_ok(
      kHead + "[0005]\nParameterName=UNSIGNED8\nDataType=0x0007\nAccessType=const\nDefaultValue=8\n");
  EXPECT_NE(m.find(0x0005, 0), nullptr);
}

TEST(EdsReader, ErrorsNameFileAndLine) {
  EXPECT_EQ(
      parse_error(kHead + "[2000]\nParameterName=x\nDataType=0x0007\nAccessType=rw\n"),
      "t.eds:21: object [2000] is in none of [MandatoryObjects], [OptionalObjects], [ManufacturerObjects]");
  EXPECT_EQ(parse_error("[FileInfo]\n[DeviceInfo]\n"), "t.eds:2: missing section [MandatoryObjects]");
  EXPECT_EQ(parse_error(""), "t.eds:1: missing section [FileInfo]");
}

TEST(EdsReader, ParseFileReadsFromDiskAndReportsUnreadableFiles) {
  const ParseResult r = parse_file(std::string(MB2CO_DOCS_DIR) + "/mb2co-ionode.eds");
  ASSERT_TRUE(r) << r.error.text();
  EXPECT_NE(r.model->find(0x1018, 1), nullptr);
  const ParseResult missing = parse_file("/nonexistent/x.eds");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error.text(), "/nonexistent/x.eds: cannot open: No such file or directory");
}

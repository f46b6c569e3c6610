// The entries every mb2co node has: data types (0001h–0007h, 0020h–0023h) and
// the CiA 301 communication area (1000h–1A03h); the rows of a service the
// image's profile leaves out are absent (MB2CO_WITH_*, profiles/profile.h). A node's OD list is
//   MB2CO_OD_DATA_TYPES(N, S)
//   MB2CO_OD_COMM_1000(N, S, <1000h..1018h parameters>)
//   MB2CO_OD_PDOS(...)   per-PDO defaults
//   ... its application entries (2000h and up), in ascending order.
#pragma once
// The OD lists and their macros are tables, one row a line: not reflowed.
// clang-format off
#include "canopen/od.h"
#include "canopen/od_define.h"

namespace mb2co {
namespace canopen {
/// The write handlers of the entries below, each called with the Node
/// (kOdOwnerNode) as OdWriteHandler says; defined in node.cpp (friends of
/// the Node: they reach its services). One per entry kind, named in its
/// rows' hook column through MB2CO_OD_COMM_HANDLERS.
struct NodeHandlers {
  static OdWriteFunction error_control;       ///< 1017h, 100Ch, 100Dh: the error control restarts
  static OdWriteFunction heartbeat_consumer;  ///< 1016h/1-4: one consumer time per node id
  static OdWriteFunction emcy;                ///< 1003h/0 (clears the history), 1014h, 1015h
  static OdWriteFunction sync;                ///< 1005h, 1006h, 1019h
  static OdWriteFunction rpdo;                ///< 1400h-1403h, 1600h-1603h
  static OdWriteFunction tpdo;                ///< 1800h-1803h, 1A00h-1A03h
  static OdWriteFunction store;               ///< 1010h "save", 1011h "load"
  static OdWriteFunction time_cob_id;         ///< 1012h (profile::kTime)
  static OdWriteFunction time_stamp;          ///< 1013h (profile::kTime)
  static OdWriteFunction node_id;             ///< the device's own node id, from the next reset communication
  static OdWriteFunction bitrate;             ///< the device's own bit rate: 125, 250, 500 or 1000 kbit/s
  static OdWriteFunction restart_request;     ///< 1 reset communication, 2 reset node; reads back 0
};
}  // namespace canopen
}  // namespace mb2co

/// The node's handler list, H(slot, function, owner): first in every OD's
/// handler table (MB2CO_OD_DEFINE), beside the rows below that name them.
#define MB2CO_OD_COMM_HANDLERS(H)                                                                              \
  H(::mb2co::canopen::kHookNmt, ::mb2co::canopen::NodeHandlers::error_control, ::mb2co::canopen::kOdOwnerNode)  \
  H(::mb2co::canopen::kHookHbConsumer, ::mb2co::canopen::NodeHandlers::heartbeat_consumer,                     \
    ::mb2co::canopen::kOdOwnerNode)                                                                            \
  H(::mb2co::canopen::kHookEmcy, ::mb2co::canopen::NodeHandlers::emcy, ::mb2co::canopen::kOdOwnerNode)          \
  H(::mb2co::canopen::kHookSync, ::mb2co::canopen::NodeHandlers::sync, ::mb2co::canopen::kOdOwnerNode)          \
  H(::mb2co::canopen::kHookRpdo, ::mb2co::canopen::NodeHandlers::rpdo, ::mb2co::canopen::kOdOwnerNode)          \
  H(::mb2co::canopen::kHookTpdo, ::mb2co::canopen::NodeHandlers::tpdo, ::mb2co::canopen::kOdOwnerNode)          \
  H(::mb2co::canopen::kHookStore, ::mb2co::canopen::NodeHandlers::store, ::mb2co::canopen::kOdOwnerNode)        \
  MB2CO_WITH_TIME(                                                                                             \
  H(::mb2co::canopen::kHookTimeCobId, ::mb2co::canopen::NodeHandlers::time_cob_id, ::mb2co::canopen::kOdOwnerNode) \
  H(::mb2co::canopen::kHookTimeStamp, ::mb2co::canopen::NodeHandlers::time_stamp, ::mb2co::canopen::kOdOwnerNode)) \
  H(::mb2co::canopen::kHookNodeId, ::mb2co::canopen::NodeHandlers::node_id, ::mb2co::canopen::kOdOwnerNode)     \
  H(::mb2co::canopen::kHookBitrate, ::mb2co::canopen::NodeHandlers::bitrate, ::mb2co::canopen::kOdOwnerNode)    \
  H(::mb2co::canopen::kHookRestartRequest, ::mb2co::canopen::NodeHandlers::restart_request,                    \
    ::mb2co::canopen::kOdOwnerNode)

namespace mb2co {
namespace canopen {
/// Capacities fixed for every node (RAM is the Uno's 2 KB).
const uint8_t kErrorHistoryLength = 4;  ///< 1003h sub1..4
const uint8_t kHbConsumers = 4;         ///< 1016h sub1..4
const uint8_t kPdoCount = 4;            ///< RPDOs and TPDOs each
static_assert(kPdoCount == kOdRecordsPerKind, "every PDO has its records (od_define.h)");
const uint8_t kPdoMaxMapped = 8;        ///< 16xxh/1Axxh sub1..8 at most (an OD may have fewer)
const uint32_t kSaveSignature = 0x65766173u;  ///< "save" (1010h)
const uint32_t kLoadSignature = 0x64616F6Cu;  ///< "load" (1011h)
}  // namespace canopen
}  // namespace mb2co

// Data-type entries: their value is the bit length; the OD sizes entries with
// them (seed 000 §2.2). 0002h–0007h double as dummy-mapping objects.
// Data-type entries of the other CiA 301 basic types (bit lengths; strings
// and DOMAIN by their unit), host builds only (MB2CO_CONFIG_WIDE_TYPES: the
// Uno's flash); not mappable (dummies are 0002h-0007h).
#define MB2CO_OD_DATA_TYPE_ROW(N, index, id, type, name) \
  N(index, 0, id, U32, CONST, 0, kHookNone, ::mb2co::canopen::od_type_bit_length(type), name)
#define MB2CO_OD_DATA_TYPES_WIDE(N, S) MB2CO_WITH_WIDE_TYPES(                                                   \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0008, x0008_0_real32, kReal32, "REAL32")                                \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0009, x0009_0_visibleString, kVisibleString, "VISIBLE_STRING")          \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x000A, x000A_0_octetString, kOctetString, "OCTET_STRING")                \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x000B, x000B_0_unicodeString, kUnicodeString, "UNICODE_STRING")          \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x000C, x000C_0_timeOfDay, kTimeOfDay, "TIME_OF_DAY")                     \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x000D, x000D_0_timeDifference, kTimeDifference, "TIME_DIFFERENCE")       \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x000F, x000F_0_domain, kDomain, "DOMAIN")                                \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0010, x0010_0_integer24, kInteger24, "INTEGER24")                       \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0011, x0011_0_real64, kReal64, "REAL64")                                \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0012, x0012_0_integer40, kInteger40, "INTEGER40")                       \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0013, x0013_0_integer48, kInteger48, "INTEGER48")                       \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0014, x0014_0_integer56, kInteger56, "INTEGER56")                       \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0015, x0015_0_integer64, kInteger64, "INTEGER64")                       \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0016, x0016_0_unsigned24, kUnsigned24, "UNSIGNED24")                    \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0018, x0018_0_unsigned40, kUnsigned40, "UNSIGNED40")                    \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x0019, x0019_0_unsigned48, kUnsigned48, "UNSIGNED48")                    \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x001A, x001A_0_unsigned56, kUnsigned56, "UNSIGNED56")                    \
  MB2CO_OD_DATA_TYPE_ROW(N, 0x001B, x001B_0_unsigned64, kUnsigned64, "UNSIGNED64"))
#define MB2CO_OD_DATA_TYPES(N, S)                                                                                 \
  N(0x0001, 0, x0001_0_boolean, U32, CONST, 0, kHookNone, 1, "BOOLEAN")                                           \
  N(0x0002, 0, x0002_0_integer8, U32, CONST, kAttrPdo, kHookNone, 8, "INTEGER8")                                  \
  N(0x0003, 0, x0003_0_integer16, U32, CONST, kAttrPdo, kHookNone, 16, "INTEGER16")                               \
  N(0x0004, 0, x0004_0_integer32, U32, CONST, kAttrPdo, kHookNone, 32, "INTEGER32")                               \
  N(0x0005, 0, x0005_0_unsigned8, U32, CONST, kAttrPdo, kHookNone, 8, "UNSIGNED8")                                \
  N(0x0006, 0, x0006_0_unsigned16, U32, CONST, kAttrPdo, kHookNone, 16, "UNSIGNED16")                             \
  N(0x0007, 0, x0007_0_unsigned32, U32, CONST, kAttrPdo, kHookNone, 32, "UNSIGNED32")                             \
  MB2CO_OD_DATA_TYPES_WIDE(N, S)                                                                                  \
  MB2CO_WITH_TYPE_DESCRIPTIONS(                                                                                   \
  N(0x0020, 0, x0020_0_highestSubIndex, U8, CONST, 0, kHookNone, 6, "PDO_COMM_PAR: highest sub-index")            \
  N(0x0020, 1, x0020_1_cobIdType, U16, CONST, 0, kHookNone, 0x0007, "COB-ID type")                                \
  N(0x0020, 2, x0020_2_transmissionTypeType, U16, CONST, 0, kHookNone, 0x0005, "transmission type type")          \
  N(0x0020, 3, x0020_3_inhibitTimeType, U16, CONST, 0, kHookNone, 0x0006, "inhibit time type")                    \
  N(0x0020, 4, x0020_4_reservedType, U16, CONST, 0, kHookNone, 0x0005, "reserved type")                           \
  N(0x0020, 5, x0020_5_eventTimerType, U16, CONST, 0, kHookNone, 0x0006, "event timer type")                      \
  N(0x0020, 6, x0020_6_syncStartValueType, U16, CONST, 0, kHookNone, 0x0005, "SYNC start value type")             \
  N(0x0021, 0, x0021_0_highestSubIndex, U8, CONST, 0, kHookNone, 8, "PDO_MAPPING: highest sub-index")             \
  N(0x0021, 1, x0021_1_mappingEntryType, U16, CONST, 0, kHookNone, 0x0007, "mapping entry type")                  \
  N(0x0022, 0, x0022_0_highestSubIndex, U8, CONST, 0, kHookNone, 3, "SDO_PARAMETER: highest sub-index")           \
  N(0x0022, 1, x0022_1_cobIdClientToServerType, U16, CONST, 0, kHookNone, 0x0007, "COB-ID client to server type") \
  N(0x0022, 2, x0022_2_cobIdServerToClientType, U16, CONST, 0, kHookNone, 0x0007, "COB-ID server to client type") \
  N(0x0022, 3, x0022_3_clientNodeIdType, U16, CONST, 0, kHookNone, 0x0005, "node-ID of the SDO client type")      \
  N(0x0023, 0, x0023_0_highestSubIndex, U8, CONST, 0, kHookNone, 4, "IDENTITY: highest sub-index")                \
  N(0x0023, 1, x0023_1_vendorIdType, U16, CONST, 0, kHookNone, 0x0007, "vendor-ID type")                          \
  N(0x0023, 2, x0023_2_productCodeType, U16, CONST, 0, kHookNone, 0x0007, "product code type")                    \
  N(0x0023, 3, x0023_3_revisionNumberType, U16, CONST, 0, kHookNone, 0x0007, "revision number type")              \
  N(0x0023, 4, x0023_4_serialNumberType, U16, CONST, 0, kHookNone, 0x0007, "serial number type"))

// 1000h–1200h. DEVTYPE: device type default (the node may set it at start),
// NAME/HW/SW: texts of 1008h–100Ah, VENDOR/PRODUCT/REVISION: 1018h,
// HEARTBEAT_MS: default producer heartbeat time 1017h.
#define MB2CO_OD_COMM_1000(N, S, DEVTYPE, NAME, HW, SW, VENDOR, PRODUCT, REVISION, HEARTBEAT_MS)                     \
  N(0x1000, 0, x1000_0_deviceType, U32, RO, 0, kHookNone, DEVTYPE, "Device type")                                    \
  N(0x1001, 0, x1001_0_errorRegister, U8, RO, kAttrPdo, kHookNone, 0, "Error register")                              \
  N(0x1003, 0, x1003_0_errorCount, U8, RW, 0, kHookEmcy, 0, "Pre-defined error field: number of errors")             \
  N(0x1003, 1, x1003_1_standardErrorField1, U32, RO, 0, kHookNone, 0, "Standard error field 1")                      \
  N(0x1003, 2, x1003_2_standardErrorField2, U32, RO, 0, kHookNone, 0, "Standard error field 2")                      \
  N(0x1003, 3, x1003_3_standardErrorField3, U32, RO, 0, kHookNone, 0, "Standard error field 3")                      \
  N(0x1003, 4, x1003_4_standardErrorField4, U32, RO, 0, kHookNone, 0, "Standard error field 4")                      \
  N(0x1005, 0, x1005_0_cobIdSync, U32, RW, 0, kHookSync, 0x80, "COB-ID SYNC message")                                \
  N(0x1006, 0, x1006_0_communicationCyclePeriod, U32, RW, 0, kHookSync, 0, "Communication cycle period (us)")        \
  S(0x1008, 0, x1008_0_deviceName, CONST, kHookNone, 0, NAME, "Manufacturer device name")                            \
  S(0x1009, 0, x1009_0_hardwareVersion, CONST, kHookNone, 0, HW, "Manufacturer hardware version")                    \
  S(0x100A, 0, x100A_0_softwareVersion, CONST, kHookNone, 0, SW, "Manufacturer software version")                    \
  MB2CO_WITH_GUARDING(                                                                                               \
  N(0x100C, 0, x100C_0_guardTime, U16, RW, 0, kHookNmt, 0, "Guard time (ms)")                                        \
  N(0x100D, 0, x100D_0_lifeTimeFactor, U8, RW, 0, kHookNmt, 0, "Life time factor"))                                  \
  N(0x1010, 0, x1010_0_highestSubIndex, U8, CONST, 0, kHookNone, 1, "Store parameters: highest sub-index")           \
  N(0x1010, 1, x1010_1_saveAllParameters, U32, RW, 0, kHookStore, 1, "Save all parameters")                          \
  MB2CO_WITH_RESTORE_DEFAULTS(                                                                                       \
  N(0x1011, 0, x1011_0_highestSubIndex, U8, CONST, 0, kHookNone, 1, "Restore default parameters: highest sub-index") \
  N(0x1011, 1, x1011_1_restoreAllDefaults, U32, RW, 0, kHookStore, 1, "Restore all default parameters"))             \
  MB2CO_WITH_TIME(                                                                                                   \
  N(0x1012, 0, x1012_0_cobIdTime, U32, RW, 0, kHookTimeCobId, 0x00000100, "COB-ID TIME (bit 31 consumer, 30 producer)")   \
  N(0x1013, 0, x1013_0_highResolutionTimeStamp, U32, RW, kAttrPdo | kAttrCommand, kHookTimeStamp, 0, "High resolution time stamp (us since 1984-01-01, mod 2^32)")) \
  N(0x1014, 0, x1014_0_cobIdEmcy, U32, RW, kAttrNodeId, kHookEmcy, 0x80, "COB-ID EMCY")                              \
  N(0x1015, 0, x1015_0_inhibitTimeEmcy, U16, RW, 0, kHookEmcy, 0, "Inhibit time EMCY (100 us)")                      \
  N(0x1016, 0, x1016_0_highestSubIndex, U8, CONST, 0, kHookNone, 4, "Consumer heartbeat time: highest sub-index")    \
  N(0x1016, 1, x1016_1_consumerHeartbeatTime1, U32, RW, 0, kHookHbConsumer, 0, "Consumer heartbeat time 1")          \
  N(0x1016, 2, x1016_2_consumerHeartbeatTime2, U32, RW, 0, kHookHbConsumer, 0, "Consumer heartbeat time 2")          \
  N(0x1016, 3, x1016_3_consumerHeartbeatTime3, U32, RW, 0, kHookHbConsumer, 0, "Consumer heartbeat time 3")          \
  N(0x1016, 4, x1016_4_consumerHeartbeatTime4, U32, RW, 0, kHookHbConsumer, 0, "Consumer heartbeat time 4")          \
  N(0x1017, 0, x1017_0_producerHeartbeatTime, U16, RW, 0, kHookNmt, HEARTBEAT_MS, "Producer heartbeat time (ms)")    \
  N(0x1018, 0, x1018_0_highestSubIndex, U8, CONST, 0, kHookNone, 4, "Identity object: highest sub-index")            \
  N(0x1018, 1, x1018_1_vendorId, U32, CONST, 0, kHookNone, VENDOR, "Vendor-ID")                                      \
  N(0x1018, 2, x1018_2_productCode, U32, CONST, 0, kHookNone, PRODUCT, "Product code")                               \
  N(0x1018, 3, x1018_3_revisionNumber, U32, CONST, 0, kHookNone, REVISION, "Revision number")                        \
  N(0x1018, 4, x1018_4_serialNumber, U32, RO, 0, kHookNone, 0, "Serial number")                                      \
  N(0x1019, 0, x1019_0_syncCounterOverflow, U8, RW, 0, kHookSync, 0, "Synchronous counter overflow value")           \
  N(0x1200, 0, x1200_0_highestSubIndex, U8, CONST, 0, kHookNone, 2, "SDO server parameter: highest sub-index")       \
  N(0x1200, 1, x1200_1_cobIdClientToServer, U32, CONST, kAttrNodeId, kHookNone, 0x600, "COB-ID client to server")    \
  N(0x1200, 2, x1200_2_cobIdServerToClient, U32, CONST, kAttrNodeId, kHookNone, 0x580, "COB-ID server to client")

// PDO communication records. COBID is relative to the node id when FLAGS has
// kAttrNodeId (the default connection set). Sub-index 4 is CiA 301's reserved
// entry: absent, so any access answers 06090011h. RPDOs stop at sub 5.
// ID is the record's identifier prefix x<index> (x1400): its rows are named
// x1400_1_cobId, x1400_2_transmissionType, ... (od_define.h).
// An OD has kPdoCount records of each kind (communication and mapping, RPDO
// and TPDO) or none, made with one macro per kind and the same FLAGS (and
// COUNT of mapping entries): the OD keeps one template record per kind
// (od_define.h, OdRecordShape; MB2CO_OD_DEFINE refuses records that differ
// but for their index, values and defaults).
#define MB2CO_OD_RPDO_COMM(N, INDEX, ID, COBID, FLAGS, TTYPE, EVENT, NAME)                          \
  N(INDEX, 0, ID##_0_highestSubIndex, U8, CONST, 0, kHookNone, 5, NAME ": highest sub-index")       \
  N(INDEX, 1, ID##_1_cobId, U32, RW, FLAGS, kHookRpdo, COBID, NAME ": COB-ID")                  \
  N(INDEX, 2, ID##_2_transmissionType, U8, RW, 0, kHookRpdo, TTYPE, NAME ": transmission type") \
  N(INDEX, 3, ID##_3_inhibitTime, U16, RW, 0, kHookRpdo, 0, NAME ": inhibit time (unused)")     \
  N(INDEX, 5, ID##_5_eventTimer, U16, RW, 0, kHookRpdo, EVENT, NAME ": event timer (ms)")
#define MB2CO_OD_TPDO_COMM(N, INDEX, ID, COBID, FLAGS, TTYPE, INHIBIT, EVENT, NAME)                   \
  N(INDEX, 0, ID##_0_highestSubIndex, U8, CONST, 0, kHookNone, 6, NAME ": highest sub-index")         \
  N(INDEX, 1, ID##_1_cobId, U32, RW, FLAGS, kHookTpdo, COBID, NAME ": COB-ID")                    \
  N(INDEX, 2, ID##_2_transmissionType, U8, RW, 0, kHookTpdo, TTYPE, NAME ": transmission type")   \
  N(INDEX, 3, ID##_3_inhibitTime, U16, RW, 0, kHookTpdo, INHIBIT, NAME ": inhibit time (100 us)") \
  N(INDEX, 5, ID##_5_eventTimer, U16, RW, 0, kHookTpdo, EVENT, NAME ": event timer (ms)")         \
  N(INDEX, 6, ID##_6_syncStartValue, U8, RW, 0, kHookTpdo, 0, NAME ": SYNC start value")

// One PDO mapping record (RPDO: 160n, TPDO: 1A0n): COUNT entries M1..M8;
// ID as above (x1600_0_mappedCount, x1600_1_mappedObject1, ...).
#define MB2CO_OD_PDO_MAP(N, INDEX, ID, HOOK, COUNT, M1, M2, M3, M4, M5, M6, M7, M8, NAME)    \
  N(INDEX, 0, ID##_0_mappedCount, U8, RW, 0, HOOK, COUNT, NAME ": number of mapped objects") \
  N(INDEX, 1, ID##_1_mappedObject1, U32, RW, 0, HOOK, M1, NAME ": mapped object 1")          \
  N(INDEX, 2, ID##_2_mappedObject2, U32, RW, 0, HOOK, M2, NAME ": mapped object 2")          \
  N(INDEX, 3, ID##_3_mappedObject3, U32, RW, 0, HOOK, M3, NAME ": mapped object 3")          \
  N(INDEX, 4, ID##_4_mappedObject4, U32, RW, 0, HOOK, M4, NAME ": mapped object 4")          \
  N(INDEX, 5, ID##_5_mappedObject5, U32, RW, 0, HOOK, M5, NAME ": mapped object 5")          \
  N(INDEX, 6, ID##_6_mappedObject6, U32, RW, 0, HOOK, M6, NAME ": mapped object 6")          \
  N(INDEX, 7, ID##_7_mappedObject7, U32, RW, 0, HOOK, M7, NAME ": mapped object 7")          \
  N(INDEX, 8, ID##_8_mappedObject8, U32, RW, 0, HOOK, M8, NAME ": mapped object 8")

// The same with 4 entries (saves 16 bytes of RAM per PDO on the Uno).
#define MB2CO_OD_PDO_MAP4(N, INDEX, ID, HOOK, COUNT, M1, M2, M3, M4, NAME)                   \
  N(INDEX, 0, ID##_0_mappedCount, U8, RW, 0, HOOK, COUNT, NAME ": number of mapped objects") \
  N(INDEX, 1, ID##_1_mappedObject1, U32, RW, 0, HOOK, M1, NAME ": mapped object 1")          \
  N(INDEX, 2, ID##_2_mappedObject2, U32, RW, 0, HOOK, M2, NAME ": mapped object 2")          \
  N(INDEX, 3, ID##_3_mappedObject3, U32, RW, 0, HOOK, M3, NAME ": mapped object 3")          \
  N(INDEX, 4, ID##_4_mappedObject4, U32, RW, 0, HOOK, M4, NAME ": mapped object 4")

/// A mapping entry: index, sub-index, length in bits (CiA 301 §7.4.8.3).
#define MB2CO_PDO_MAP_ENTRY(index, sub, bits) \
  ((static_cast<uint32_t>(index) << 16) | (static_cast<uint32_t>(sub) << 8) | (bits))
// clang-format on

// Object Dictionary of the gateway: the CiA 301 communication area, the
// station's line state (RUN/STOP2, seed 000 §10), CiA 401 inputs/outputs, the
// latency-lab timestamps, and the Modbus register maps (2400h–2403h) that bind
// every Modbus table to OD entries. docs/od-gateway.md and the EDS are printed
// from this very list by mb2co-od.
#pragma once
// The OD lists and their macros are tables, one row a line: not reflowed.
// clang-format off
#include "canopen/od_comm.h"
#include "canopen/od_define.h"

namespace mb2co {
namespace gateway {

/// Capacities of the Modbus maps (sub-entries of 2400h–2403h). Host builds
/// map the process values of 2500h too (profile::kWideTypes).
const uint8_t kHoldingMapSize = profile::kWideTypes ? 14 : 12;
const uint8_t kInputMapSize = 21;
const uint8_t kCoilMapSize = 2;
const uint8_t kDiscreteMapSize = 8;
/// 2300h's subs: with TIME (profile::kTime) also when the common clock was
/// last set (2300h/4); the stamps 2300h/1-3 are on that clock from then on.
const uint8_t kLatencyLabSubs = profile::kTime ? 4 : 3;

/// The gateway's own handler slots and owners (od.h): the RUN command is
/// the gateway's (its line application), the Modbus maps the register
/// bank's. Node id, bit rate and restart request are the node's
/// (od_comm.h: one policy for every device).
const uint8_t kHookRunCommand = canopen::kHookApp;
const uint8_t kHookRegisterMap = canopen::kHookApp + 1;
const uint8_t kOwnerGateway = 1;
const uint8_t kOwnerRegisterBank = 2;
/// Defined in gateway.cpp (run_command) and od_register_bank.cpp (register_map).
struct GatewayHandlers {
  static canopen::OdWriteFunction run_command;   ///< 2100h/1: the PC's RUN command to the line application
  static canopen::OdWriteFunction register_map;  ///< 2400h-2403h: what a Modbus map may name
};
/// The gateway's handler list, H(slot, function, owner) (MB2CO_OD_DEFINE).
#define MB2CO_GATEWAY_HANDLERS(H)                                                                              \
  H(::mb2co::gateway::kHookRunCommand, ::mb2co::gateway::GatewayHandlers::run_command, ::mb2co::gateway::kOwnerGateway) \
  H(::mb2co::gateway::kHookRegisterMap, ::mb2co::gateway::GatewayHandlers::register_map,                       \
    ::mb2co::gateway::kOwnerRegisterBank)

#define MB2CO_MAP MB2CO_PDO_MAP_ENTRY
#define MB2CO_GW_MAP_ENTRY(N, INDEX, SUB, ID, HOOK, DEF, NAME) N(INDEX, SUB, ID, U32, RW, 0, HOOK, DEF, NAME)

// Default Modbus map (docs/register-map.md is generated from it).
#define MB2CO_GATEWAY_OD(N, S)                                                                                                        \
  MB2CO_OD_DATA_TYPES(N, S)                                                                                                           \
  MB2CO_OD_COMM_1000(N, S, 0x00030191, "mb2co gateway", "Uno+MCP2515", "0.1.0", 0, 0x0B2C, 1, 100)                                    \
  MB2CO_OD_RPDO_COMM(N, 0x1400, x1400, 0x17F, kAttrNodeId, 254, 0, "RPDO1 previous station")                                          \
  MB2CO_OD_RPDO_COMM(N, 0x1401, x1401, 0x181, kAttrNodeId, 254, 0, "RPDO2 next station")                                              \
  MB2CO_OD_RPDO_COMM(N, 0x1402, x1402, 0x27F, kAttrNodeId, 254, 0, "RPDO3 remote buttons")                                            \
  MB2CO_OD_RPDO_COMM(N, 0x1403, x1403, 0x80000500, kAttrNodeId, 254, 0, "RPDO4")                                                      \
  MB2CO_OD_PDO_MAP4(N, 0x1600, x1600, kHookRpdo, 2, MB2CO_MAP(0x2110, 1, 8), MB2CO_MAP(0x2110, 2, 16), 0,                          \
                    0, "RPDO1 mapping")                                                                                               \
  MB2CO_OD_PDO_MAP4(N, 0x1601, x1601, kHookRpdo, 2, MB2CO_MAP(0x2120, 1, 8), MB2CO_MAP(0x0006, 0, 16), 0,                          \
                    0, "RPDO2 mapping")                                                                                               \
  MB2CO_OD_PDO_MAP4(N, 0x1602, x1602, kHookRpdo, 1, MB2CO_MAP(0x2130, 1, 8), 0, 0, 0, "RPDO3 mapping")                             \
  MB2CO_OD_PDO_MAP4(N, 0x1603, x1603, kHookRpdo, 0, 0, 0, 0, 0, "RPDO4 mapping")                                                   \
  MB2CO_OD_TPDO_COMM(N, 0x1800, x1800, 0x180, kAttrNodeId, 254, 100, 100, "TPDO1 line state")                                         \
  MB2CO_OD_TPDO_COMM(N, 0x1801, x1801, 0x280, kAttrNodeId, 254, 0, 0, "TPDO2 buttons")                                                \
  MB2CO_OD_TPDO_COMM(N, 0x1802, x1802, 0x80000380, kAttrNodeId, 254, 0, 0, "TPDO3")                                                   \
  MB2CO_OD_TPDO_COMM(N, 0x1803, x1803, 0x80000480, kAttrNodeId, 254, 0, 0, "TPDO4")                                                   \
  MB2CO_OD_PDO_MAP4(N, 0x1A00, x1A00, kHookTpdo, 2, MB2CO_MAP(0x2100, 2, 8), MB2CO_MAP(0x2100, 3, 16), 0,                          \
                    0, "TPDO1 mapping")                                                                                               \
  MB2CO_OD_PDO_MAP4(N, 0x1A01, x1A01, kHookTpdo, 1, MB2CO_MAP(0x6000, 1, 8), 0, 0, 0, "TPDO2 mapping")                             \
  MB2CO_OD_PDO_MAP4(N, 0x1A02, x1A02, kHookTpdo, MB2CO_WIDE_TYPES_OR(1, 0), MB2CO_WIDE_TYPES_OR(MB2CO_MAP(0x2500, 1, 32), 0), 0, 0, 0,     \
                    "TPDO3 mapping")                                                                                                  \
  MB2CO_OD_PDO_MAP4(N, 0x1A03, x1A03, kHookTpdo, MB2CO_WIDE_TYPES_OR(1, 0), MB2CO_WIDE_TYPES_OR(MB2CO_MAP(0x2500, 2, 64), 0), 0, 0, 0,     \
                    "TPDO4 mapping")                                                                                                  \
  N(0x2000, 0, x2000_0_highestSubIndex, U8, CONST, 0, kHookNone, 10, "Station configuration: highest sub-index")                       \
  N(0x2000, 1, x2000_1_nodeId, U8, RW, 0, kHookNodeId, 1, "Station configuration: node id (from next reset)")                            \
  N(0x2000, 2, x2000_2_bitrateKbit, U16, RW, 0, kHookBitrate, 500, "Station configuration: CAN bit rate kbit/s (from next reset)")        \
  N(0x2000, 3, x2000_3_topology, U8, RW, 0, kHookNone, 1, "Station configuration: topology 0 chain, 1 ring")                          \
  N(0x2000, 4, x2000_4_stationCount, U8, RW, 0, kHookNone, 4, "Station configuration: stations in the line")                          \
  N(0x2000, 5, x2000_5_modbusAddress, U8, RW, 0, kHookNone, 1, "Station configuration: Modbus address (from next reset)")             \
  N(0x2000, 6, x2000_6_debounceMs, U16, RW, 0, kHookNone, 20, "Station configuration: button debounce ms")                            \
  N(0x2000, 7, x2000_7_pdoConfigAsStored, U8, RW, 0, kHookNone, 0, "Station configuration: PDOs and 1016h 0 derived, 1 as stored")    \
  N(0x2000, 8, x2000_8_selfStarting, U8, RW, 0, kHookNone, 1, "Station configuration: 1 enter operational by itself, 0 wait for NMT") \
  N(0x2000, 9, x2000_9_modbusWatchdogMs, U16, RW, 0, kHookNone, 2000, "Station configuration: Modbus watchdog ms (0 off)")            \
  N(0x2000, 10, x2000_10_networkAccess, U8, RW, 0, kHookNone, 1, "Station configuration: Modbus FC 2Bh/0Dh to the network 1 on, 0 off") \
  N(0x2001, 0, x2001_0_restartRequest, U8, RW, kAttrCommand, kHookRestartRequest, 0, "Restart request: 1 reset communication, 2 reset node")     \
  N(0x2002, 0, x2002_0_nmtState, U8, RO, 0, kHookNone, 0, "NMT state of this node")                                                   \
  N(0x2003, 0, x2003_0_storageDamageCount, U8, RO, 0, kHookNone, 0, "Resets since power-on that found a damaged saved set")        \
  N(0x2100, 0, x2100_0_highestSubIndex, U8, CONST, 0, kHookNone, 6, "Own station: highest sub-index")                                 \
  N(0x2100, 1, x2100_1_runCommand, U8, RW, kAttrCommand, ::mb2co::gateway::kHookRunCommand, 0, "Own station: RUN command from the PC")                         \
  N(0x2100, 2, x2100_2_runState, U8, RO, kAttrPdo, kHookNone, 0, "Own station: RUN state")                                            \
  N(0x2100, 3, x2100_3_stop2Count, U16, RO, kAttrPdo, kHookNone, 0, "Own station: STOP2 event counter")                               \
  N(0x2100, 4, x2100_4_stopCause, U8, RO, 0, kHookNone, 0, "Own station: stop cause")                                                 \
  N(0x2100, 5, x2100_5_startCount, U16, RO, 0, kHookNone, 0, "Own station: START press counter")                                      \
  N(0x2100, 6, x2100_6_stopCount, U16, RO, 0, kHookNone, 0, "Own station: STOP press counter")                                        \
  N(0x2110, 0, x2110_0_highestSubIndex, U8, CONST, 0, kHookNone, 4, "Previous station: highest sub-index")                            \
  N(0x2110, 1, x2110_1_prevRunState, U8, RW, kAttrPdo | kAttrCommand, kHookNone, 0, "Previous station: RUN state")                    \
  N(0x2110, 2, x2110_2_prevStop2Count, U16, RW, kAttrPdo | kAttrCommand, kHookNone, 0, "Previous station: STOP2 event counter")       \
  N(0x2110, 3, x2110_3_prevStatus, U8, RO, 0, kHookNone, 0, "Previous station: status 0 unknown, 1 alive, 2 none; +80h no TPDO1 yet")\
  N(0x2110, 4, x2110_4_prevNodeId, U8, RO, 0, kHookNone, 0, "Previous station: node id")                                              \
  N(0x2120, 0, x2120_0_highestSubIndex, U8, CONST, 0, kHookNone, 4, "Next station: highest sub-index")                                \
  N(0x2120, 1, x2120_1_nextRunState, U8, RW, kAttrPdo | kAttrCommand, kHookNone, 0, "Next station: RUN state")                        \
  N(0x2120, 2, x2120_2_nextStop2Count, U16, RW, kAttrPdo | kAttrCommand, kHookNone, 0, "Next station: STOP2 event counter")           \
  N(0x2120, 3, x2120_3_nextStatus, U8, RO, 0, kHookNone, 0, "Next station: status 0 unknown, 1 alive, 2 none; +80h no TPDO1 yet")    \
  N(0x2120, 4, x2120_4_nextNodeId, U8, RO, 0, kHookNone, 0, "Next station: node id")                                                  \
  N(0x2130, 0, x2130_0_highestSubIndex, U8, CONST, 0, kHookNone, 2, "Remote buttons: highest sub-index")                              \
  N(0x2130, 1, x2130_1_remoteButtons, U8, RW, kAttrPdo | kAttrCommand, kHookNone, 0, "Remote buttons: levels of the watched station") \
  N(0x2130, 2, x2130_2_watchedNodeId, U8, RW, 0, kHookNone, 0, "Remote buttons: watched node id (0 previous station)")                \
  N(0x2140, 0, x2140_0_highestSubIndex, U8, CONST, 0, kHookNone, 3, "Buttons: highest sub-index")                                     \
  N(0x2140, 1, x2140_1_startPressed, BOOL, RO, kAttrPdo, kHookNone, 0, "Buttons: START pressed")                                      \
  N(0x2140, 2, x2140_2_stopPressed, BOOL, RO, kAttrPdo, kHookNone, 0, "Buttons: STOP pressed")                                        \
  N(0x2140, 3, x2140_3_stop2Pressed, BOOL, RO, kAttrPdo, kHookNone, 0, "Buttons: STOP2 pressed")                                      \
  N(0x2200, 0, x2200_0_leds, U8, RO, kAttrPdo, kHookNone, 0, "LEDs as driven: RUN-self, RUN-prev, RUN-next, lab")                     \
  N(0x2300, 0, x2300_0_highestSubIndex, U8, CONST, 0, kHookNone, kLatencyLabSubs, "Latency lab: highest sub-index")                 \
  N(0x2300, 1, x2300_1_buttonEdgeUs, U32, RO, 0, kHookNone, 0, "Latency lab: last button edge (us)")                                  \
  N(0x2300, 2, x2300_2_labLedUs, U32, RO, 0, kHookNone, 0, "Latency lab: last lab LED change (us)")                                   \
  N(0x2300, 3, x2300_3_remoteButtonsUs, U32, RO, 0, kHookNone, 0, "Latency lab: last remote buttons arrival (us)")                    \
  MB2CO_WITH_TIME(                                                                                                                      \
  N(0x2300, 4, x2300_4_commonClockSetUs, U32, RO, 0, kHookNone, 0, "Latency lab: common clock last set (us, 0 never)"))                  \
  N(0x2400, 0, x2400_0_holdingMapCount, U8, RW, 0, ::mb2co::gateway::kHookRegisterMap, kHoldingMapSize, "Modbus holding registers: mapped entries")             \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 1, x2400_1_holdingMap1, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2100, 1, 8), "HR map 1")                                \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 2, x2400_2_holdingMap2, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x6200, 1, 8), "HR map 2")                                \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 3, x2400_3_holdingMap3, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2000, 1, 8), "HR map 3")                                \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 4, x2400_4_holdingMap4, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2000, 2, 16), "HR map 4")                               \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 5, x2400_5_holdingMap5, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2000, 3, 8), "HR map 5")                                \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 6, x2400_6_holdingMap6, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2000, 4, 8), "HR map 6")                                \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 7, x2400_7_holdingMap7, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2000, 5, 8), "HR map 7")                                \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 8, x2400_8_holdingMap8, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2000, 6, 16), "HR map 8")                               \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 9, x2400_9_holdingMap9, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x1017, 0, 16), "HR map 9")                               \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 10, x2400_10_holdingMap10, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x1006, 0, 32), "HR map 10")                           \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 11, x2400_11_holdingMap11, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x1010, 1, 32), "HR map 11")                           \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 12, x2400_12_holdingMap12, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2001, 0, 8), "HR map 12")                            \
  MB2CO_WITH_WIDE_TYPES(                                                                                                                      \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 13, x2400_13_holdingMap13, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2500, 1, 32), "HR map 13")                           \
  MB2CO_GW_MAP_ENTRY(N, 0x2400, 14, x2400_14_holdingMap14, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2500, 2, 64), "HR map 14"))                          \
  N(0x2401, 0, x2401_0_inputMapCount, U8, RW, 0, ::mb2co::gateway::kHookRegisterMap, 21, "Modbus input registers: mapped entries")                              \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 1, x2401_1_inputMap1, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x6000, 1, 8), "IR map 1")                                  \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 2, x2401_2_inputMap2, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2100, 2, 8), "IR map 2")                                  \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 3, x2401_3_inputMap3, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2100, 3, 16), "IR map 3")                                 \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 4, x2401_4_inputMap4, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2100, 4, 8), "IR map 4")                                  \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 5, x2401_5_inputMap5, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2100, 5, 16), "IR map 5")                                 \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 6, x2401_6_inputMap6, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2100, 6, 16), "IR map 6")                                 \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 7, x2401_7_inputMap7, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2110, 1, 8), "IR map 7")                                  \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 8, x2401_8_inputMap8, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2110, 2, 16), "IR map 8")                                 \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 9, x2401_9_inputMap9, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2110, 3, 8), "IR map 9")                                  \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 10, x2401_10_inputMap10, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2120, 1, 8), "IR map 10")                              \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 11, x2401_11_inputMap11, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2120, 3, 8), "IR map 11")                              \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 12, x2401_12_inputMap12, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2200, 0, 8), "IR map 12")                              \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 13, x2401_13_inputMap13, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2300, 1, 32), "IR map 13")                             \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 14, x2401_14_inputMap14, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2300, 2, 32), "IR map 14")                             \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 15, x2401_15_inputMap15, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2300, 3, 32), "IR map 15")                             \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 16, x2401_16_inputMap16, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2130, 1, 8), "IR map 16")                              \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 17, x2401_17_inputMap17, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x1001, 0, 8), "IR map 17")                              \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 18, x2401_18_inputMap18, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2110, 4, 8), "IR map 18")                              \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 19, x2401_19_inputMap19, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2120, 4, 8), "IR map 19")                              \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 20, x2401_20_inputMap20, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2002, 0, 8), "IR map 20")                              \
  MB2CO_GW_MAP_ENTRY(N, 0x2401, 21, x2401_21_inputMap21, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2003, 0, 8), "IR map 21")                              \
  N(0x2402, 0, x2402_0_coilMapCount, U8, RW, 0, ::mb2co::gateway::kHookRegisterMap, 2, "Modbus coils: mapped entries")                                          \
  MB2CO_GW_MAP_ENTRY(N, 0x2402, 1, x2402_1_coilMap1, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2100, 1, 1), "coil map 1")                                 \
  MB2CO_GW_MAP_ENTRY(N, 0x2402, 2, x2402_2_coilMap2, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x6200, 1, 1), "coil map 2")                                 \
  N(0x2403, 0, x2403_0_discreteMapCount, U8, RW, 0, ::mb2co::gateway::kHookRegisterMap, 7, "Modbus discrete inputs: mapped entries")                            \
  MB2CO_GW_MAP_ENTRY(N, 0x2403, 1, x2403_1_discreteMap1, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2140, 1, 1), "DI map 1")                               \
  MB2CO_GW_MAP_ENTRY(N, 0x2403, 2, x2403_2_discreteMap2, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2140, 2, 1), "DI map 2")                               \
  MB2CO_GW_MAP_ENTRY(N, 0x2403, 3, x2403_3_discreteMap3, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2140, 3, 1), "DI map 3")                               \
  MB2CO_GW_MAP_ENTRY(N, 0x2403, 4, x2403_4_discreteMap4, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2100, 2, 1), "DI map 4")                               \
  MB2CO_GW_MAP_ENTRY(N, 0x2403, 5, x2403_5_discreteMap5, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2110, 1, 1), "DI map 5")                               \
  MB2CO_GW_MAP_ENTRY(N, 0x2403, 6, x2403_6_discreteMap6, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2120, 1, 1), "DI map 6")                               \
  MB2CO_GW_MAP_ENTRY(N, 0x2403, 7, x2403_7_discreteMap7, ::mb2co::gateway::kHookRegisterMap, MB2CO_MAP(0x2200, 0, 1), "DI map 7")                               \
  MB2CO_GW_MAP_ENTRY(N, 0x2403, 8, x2403_8_discreteMap8, ::mb2co::gateway::kHookRegisterMap, 0, "DI map 8")                                                     \
  MB2CO_WITH_WIDE_TYPES(                                                                                                                      \
  N(0x2500, 0, x2500_0_highestSubIndex, U8, CONST, 0, kHookNone, 2, "Process values (host builds): highest sub-index")               \
  N(0x2500, 1, x2500_1_measuredValue, REAL32, RW, kAttrPdo | kAttrCommand, kHookNone, 0.0f, "Process values (host builds): measured value, REAL32") \
  N(0x2500, 2, x2500_2_eventCounter, U64, RW, kAttrPdo | kAttrCommand, kHookNone, 0, "Process values (host builds): event counter, UNSIGNED64")) \
  N(0x6000, 0, x6000_0_highestSubIndex, U8, CONST, 0, kHookNone, 1, "Read input 8-bit: highest sub-index")                            \
  N(0x6000, 1, x6000_1_readInput8Bit1, U8, RO, kAttrPdo, kHookNone, 0, "Read input 8-bit 1: START, STOP, STOP2 pressed")              \
  N(0x6200, 0, x6200_0_highestSubIndex, U8, CONST, 0, kHookNone, 1, "Write output 8-bit: highest sub-index")                          \
  N(0x6200, 1, x6200_1_writeOutput8Bit1, U8, RW, kAttrPdo | kAttrCommand, kHookNone, 0, "Write output 8-bit 1: bit 0 lab LED")

#define MB2CO_GATEWAY_LIMITS(L) \
  L(0x2000, 1, 1, 127)          \
  L(0x2000, 3, 0, 1)            \
  L(0x2000, 4, 2, 127)          \
  L(0x2000, 5, 1, 247)          \
  L(0x2000, 6, 1, 500)          \
  L(0x2000, 7, 0, 1)            \
  L(0x2000, 8, 0, 1)            \
  L(0x2001, 0, 0, 2)            \
  L(0x2100, 1, 0, 1)            \
  MB2CO_WITH_WIDE_TYPES(L(0x2500, 1, od_real32_limit(-1.0e6f), od_real32_limit(1.0e6f)))

namespace od {
using namespace ::mb2co::canopen;
MB2CO_OD_DECLARE(Gateway, MB2CO_GATEWAY_OD)
MB2CO_OD_DEFAULTS(Gateway, MB2CO_GATEWAY_OD)
}  // namespace od

}  // namespace gateway
}  // namespace mb2co
// clang-format on

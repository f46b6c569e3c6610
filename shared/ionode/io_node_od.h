// Object Dictionary of the CiA 401-style digital I/O test node: two input
// bytes (6000h), two output bytes (6200h), TPDO1 = inputs, RPDO1 = outputs,
// as the CO4011 module of seed 004 §2.11 that the frame trace talks to.
// The inputs' CiA 401 parameters (defaults as CiA 401 gives them): polarity
// 6002h (1 = bit inverted), global interrupt enable 6005h (TRUE), interrupt
// masks any change 6006h (FFh), low-to-high 6007h and high-to-low 6008h
// (00h): which changes of 6000h send TPDO1 (IoNode).
// 2001h/1-2 are the node's own id and CAN bit rate, as the gateway's
// 2000h/1-2: saved with 1010h, in force from the next reset (IoNode).
#pragma once
// The OD lists and their macros are tables, one row a line: not reflowed.
// clang-format off
#include "canopen/od_comm.h"
#include "canopen/od_define.h"

namespace mb2co {
namespace ionode {

/// The I/O node's own handler slots and owner (od.h): the input polarity
/// and the outputs are the IoNode's; node id and bit rate the node's
/// (od_comm.h: one policy for every device).
const uint8_t kHookPolarity = canopen::kHookApp;
const uint8_t kHookOutputs = canopen::kHookApp + 1;
const uint8_t kOwnerIoNode = 1;
/// Defined in io_node.cpp (friends of the IoNode).
struct IoNodeHandlers {
  static canopen::OdWriteFunction polarity;  ///< 6002h/1-2: 6000h reads the pins anew at once
  static canopen::OdWriteFunction outputs;   ///< 6200h/1-2: refused under local control or when not operational
};
/// The I/O node's handler list, H(slot, function, owner) (MB2CO_OD_DEFINE).
#define MB2CO_IO_NODE_HANDLERS(H)                                                                            \
  H(::mb2co::ionode::kHookPolarity, ::mb2co::ionode::IoNodeHandlers::polarity, ::mb2co::ionode::kOwnerIoNode) \
  H(::mb2co::ionode::kHookOutputs, ::mb2co::ionode::IoNodeHandlers::outputs, ::mb2co::ionode::kOwnerIoNode)

#define MB2CO_IO_NODE_OD(N, S)                                                                                  \
  MB2CO_OD_DATA_TYPES(N, S)                                                                                     \
  MB2CO_OD_COMM_1000(N, S, 0x00030191, "mb2co I/O node", "1.0", "0.1.0", 0, 0x401, 1, 0)                        \
  MB2CO_OD_RPDO_COMM(N, 0x1400, x1400, 0x200, kAttrNodeId, 255, 0, "RPDO1")                                     \
  MB2CO_OD_RPDO_COMM(N, 0x1401, x1401, 0x80000300, kAttrNodeId, 255, 0, "RPDO2")                                \
  MB2CO_OD_RPDO_COMM(N, 0x1402, x1402, 0x80000400, kAttrNodeId, 255, 0, "RPDO3")                                \
  MB2CO_OD_RPDO_COMM(N, 0x1403, x1403, 0x80000500, kAttrNodeId, 255, 0, "RPDO4")                                \
  MB2CO_OD_PDO_MAP(N, 0x1600, x1600, kHookRpdo, 2, MB2CO_PDO_MAP_ENTRY(0x6200, 1, 8),                        \
                   MB2CO_PDO_MAP_ENTRY(0x6200, 2, 8), 0, 0, 0, 0, 0, 0, "RPDO1 mapping")                        \
  MB2CO_OD_PDO_MAP(N, 0x1601, x1601, kHookRpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "RPDO2 mapping")                  \
  MB2CO_OD_PDO_MAP(N, 0x1602, x1602, kHookRpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "RPDO3 mapping")                  \
  MB2CO_OD_PDO_MAP(N, 0x1603, x1603, kHookRpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "RPDO4 mapping")                  \
  MB2CO_OD_TPDO_COMM(N, 0x1800, x1800, 0x180, kAttrNodeId, 255, 0, 0, "TPDO1")                                  \
  MB2CO_OD_TPDO_COMM(N, 0x1801, x1801, 0x80000280, kAttrNodeId, 255, 0, 0, "TPDO2")                             \
  MB2CO_OD_TPDO_COMM(N, 0x1802, x1802, 0x80000380, kAttrNodeId, 255, 0, 0, "TPDO3")                             \
  MB2CO_OD_TPDO_COMM(N, 0x1803, x1803, 0x80000480, kAttrNodeId, 255, 0, 0, "TPDO4")                             \
  MB2CO_OD_PDO_MAP(N, 0x1A00, x1A00, kHookTpdo, 2, MB2CO_PDO_MAP_ENTRY(0x6000, 1, 8),                        \
                   MB2CO_PDO_MAP_ENTRY(0x6000, 2, 8), 0, 0, 0, 0, 0, 0, "TPDO1 mapping")                        \
  MB2CO_OD_PDO_MAP(N, 0x1A01, x1A01, kHookTpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "TPDO2 mapping")                  \
  MB2CO_OD_PDO_MAP(N, 0x1A02, x1A02, kHookTpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "TPDO3 mapping")                  \
  MB2CO_OD_PDO_MAP(N, 0x1A03, x1A03, kHookTpdo, 0, 0, 0, 0, 0, 0, 0, 0, 0, "TPDO4 mapping")                  \
  S(0x2000, 0, x2000_0_locationLabel, RW, kHookNone, 24, "", "Location label")                                  \
  N(0x2001, 0, x2001_0_highestSubIndex, U8, CONST, 0, kHookNone, 2, "Node configuration: highest sub-index")    \
  N(0x2001, 1, x2001_1_nodeId, U8, RW, 0, kHookNodeId, 0x20, "Node configuration: node id")                        \
  N(0x2001, 2, x2001_2_bitrateKbit, U16, RW, 0, kHookBitrate, 500, "Node configuration: bit rate kbit/s")           \
  N(0x2100, 0, x2100_0_localControl, BOOL, RW, 0, kHookNone, 0, "Local control (outputs refuse network writes)") \
  N(0x2101, 0, x2101_0_inputDebounceMs, U16, RW, 0, kHookNone, 10, "Input debounce (ms)")                       \
  N(0x6000, 0, x6000_0_highestSubIndex, U8, CONST, 0, kHookNone, 2, "Read input 8-bit: highest sub-index")      \
  N(0x6000, 1, x6000_1_readInput8Bit1, U8, RO, kAttrPdo, kHookNone, 0, "Read input 8-bit 1")                    \
  N(0x6000, 2, x6000_2_readInput8Bit2, U8, RO, kAttrPdo, kHookNone, 0, "Read input 8-bit 2")                    \
  N(0x6002, 0, x6002_0_highestSubIndex, U8, CONST, 0, kHookNone, 2, "Polarity input 8-bit: highest sub-index")  \
  N(0x6002, 1, x6002_1_polarityInput8Bit1, U8, RW, 0, ::mb2co::ionode::kHookPolarity, 0, "Polarity input 8-bit 1")                   \
  N(0x6002, 2, x6002_2_polarityInput8Bit2, U8, RW, 0, ::mb2co::ionode::kHookPolarity, 0, "Polarity input 8-bit 2")                   \
  N(0x6005, 0, x6005_0_globalInterruptEnable, BOOL, RW, 0, kHookNone, 1, "Global interrupt enable digital 8-bit") \
  N(0x6006, 0, x6006_0_highestSubIndex, U8, CONST, 0, kHookNone, 2, "Interrupt mask any change 8-bit: highest sub-index") \
  N(0x6006, 1, x6006_1_interruptMaskAnyChange1, U8, RW, 0, kHookNone, 0xFF, "Interrupt mask any change 8-bit 1") \
  N(0x6006, 2, x6006_2_interruptMaskAnyChange2, U8, RW, 0, kHookNone, 0xFF, "Interrupt mask any change 8-bit 2") \
  N(0x6007, 0, x6007_0_highestSubIndex, U8, CONST, 0, kHookNone, 2, "Interrupt mask low-to-high 8-bit: highest sub-index") \
  N(0x6007, 1, x6007_1_interruptMaskLowToHigh1, U8, RW, 0, kHookNone, 0, "Interrupt mask low-to-high 8-bit 1")  \
  N(0x6007, 2, x6007_2_interruptMaskLowToHigh2, U8, RW, 0, kHookNone, 0, "Interrupt mask low-to-high 8-bit 2")  \
  N(0x6008, 0, x6008_0_highestSubIndex, U8, CONST, 0, kHookNone, 2, "Interrupt mask high-to-low 8-bit: highest sub-index") \
  N(0x6008, 1, x6008_1_interruptMaskHighToLow1, U8, RW, 0, kHookNone, 0, "Interrupt mask high-to-low 8-bit 1")  \
  N(0x6008, 2, x6008_2_interruptMaskHighToLow2, U8, RW, 0, kHookNone, 0, "Interrupt mask high-to-low 8-bit 2")  \
  N(0x6200, 0, x6200_0_highestSubIndex, U8, CONST, 0, kHookNone, 2, "Write output 8-bit: highest sub-index")    \
  N(0x6200, 1, x6200_1_writeOutput8Bit1, U8, RW, kAttrPdo | kAttrCommand, ::mb2co::ionode::kHookOutputs, 0, "Write output 8-bit 1")  \
  N(0x6200, 2, x6200_2_writeOutput8Bit2, U8, RW, kAttrPdo | kAttrCommand, ::mb2co::ionode::kHookOutputs, 0, "Write output 8-bit 2")

#define MB2CO_IO_NODE_LIMITS(L) \
  L(0x2001, 1, 1, 127)          \
  L(0x2001, 2, 125, 1000)       \
  L(0x2101, 0, 1, 250)

namespace od {
using namespace ::mb2co::canopen;
MB2CO_OD_DECLARE(IoNode, MB2CO_IO_NODE_OD)
}  // namespace od

}  // namespace ionode
}  // namespace mb2co
// clang-format on

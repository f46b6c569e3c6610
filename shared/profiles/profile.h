// What an image contains, read from its one profile header (CANopenNode's
// CO_config.h discipline: one named switch per service, one file per image).
// Every build puts exactly one profile folder on its include path, before
// shared/: shared/profiles/<image>/mb2co_profile.h (linux: mb2co-node and
// every host program; station and network: the Uno's two gateway images;
// ionode; bridge). Every translation unit of an image sees the same profile.
//
// Code outside a service never tests a switch with #if: it uses the
// constants of namespace mb2co::profile in ordinary code (the compiler drops
// what a constant turns off), or a service's own slot type (a service header
// offers an empty stand-in when its switch is off: gateway/network_service.h).
// #if on a switch is for the profile headers, this file and the code of the
// service itself.
#pragma once

#include "mb2co_profile.h"

#if !defined(MB2CO_PROFILE_NAME) || !defined(MB2CO_CONFIG_NETWORK) || !defined(MB2CO_CONFIG_GUARDING) || \
    !defined(MB2CO_CONFIG_DIAGNOSTICS) || !defined(MB2CO_CONFIG_TYPE_DESCRIPTIONS) ||                    \
    !defined(MB2CO_CONFIG_RESTORE_DEFAULTS) || !defined(MB2CO_CONFIG_SDO_BLOCK) ||                       \
    !defined(MB2CO_CONFIG_TPDO_RTR) || !defined(MB2CO_CONFIG_WIDE_TYPES) ||                              \
    !defined(MB2CO_CONFIG_MODBUS_TCP) || !defined(MB2CO_CONFIG_PROFILE_EVENTS) ||                        \
    !defined(MB2CO_CONFIG_TIME) || !defined(MB2CO_CONFIG_OD_DIRECT_GET)
#error \
    "mb2co_profile.h: every MB2CO_CONFIG_* switch must be defined (shared/profiles/station/mb2co_profile.h lists them)"
#endif

// Rows of an OD list that belong to a service: MB2CO_WITH_<SERVICE>(rows...)
// keeps them where the profile has the service and drops them elsewhere, so
// an object an image leaves out is absent from its OD, its EDS and its docs.
#if MB2CO_CONFIG_MODBUS_TCP && !MB2CO_CONFIG_NETWORK
#error \
    "mb2co_profile.h: Modbus/TCP routes FC 2Bh/0Dh's deferred answers: MB2CO_CONFIG_MODBUS_TCP needs MB2CO_CONFIG_NETWORK"
#endif

// The direct table is 12 bytes of RAM per row up to 1,024 rows, and find()
// remembers 256 answers of 8 bytes (14 KB per dictionary, canopen/od.h):
// seven times the Uno's 2 KB. It is for hosts, where the simulator calls
// every station's core on every pass.
#if MB2CO_CONFIG_OD_DIRECT_GET && defined(__AVR__)
#error \
    "mb2co_profile.h: MB2CO_CONFIG_OD_DIRECT_GET is for hosts (14 KB of RAM per OD): 0 in the Uno's profiles"
#endif

#if MB2CO_CONFIG_GUARDING
#define MB2CO_WITH_GUARDING(...) __VA_ARGS__
#else
#define MB2CO_WITH_GUARDING(...)
#endif
#if MB2CO_CONFIG_TYPE_DESCRIPTIONS
#define MB2CO_WITH_TYPE_DESCRIPTIONS(...) __VA_ARGS__
#else
#define MB2CO_WITH_TYPE_DESCRIPTIONS(...)
#endif
#if MB2CO_CONFIG_RESTORE_DEFAULTS
#define MB2CO_WITH_RESTORE_DEFAULTS(...) __VA_ARGS__
#else
#define MB2CO_WITH_RESTORE_DEFAULTS(...)
#endif
#if MB2CO_CONFIG_TIME
#define MB2CO_WITH_TIME(...) __VA_ARGS__
#else
#define MB2CO_WITH_TIME(...)
#endif
#if MB2CO_CONFIG_NETWORK
#define MB2CO_WITH_NETWORK(...) __VA_ARGS__
#else
#define MB2CO_WITH_NETWORK(...)
#endif

#if MB2CO_CONFIG_WIDE_TYPES
#define MB2CO_WITH_WIDE_TYPES(...) __VA_ARGS__
#define MB2CO_WIDE_TYPES_OR(wide, narrow) wide
#else
#define MB2CO_WITH_WIDE_TYPES(...)
#define MB2CO_WIDE_TYPES_OR(wide, narrow) narrow
#endif

namespace mb2co {
namespace profile {

/// The image's profile name (the folder of its mb2co_profile.h).
constexpr const char* kName = MB2CO_PROFILE_NAME;
/// Modbus FC 2Bh / MEI 0Dh: SDO, NMT and the network view of every node
/// from the Modbus master (gateway/network_service.h; CiA 309-2).
constexpr bool kNetwork = MB2CO_CONFIG_NETWORK != 0;
/// Node guarding and life guarding (100Ch, 100Dh); heartbeats are always in.
constexpr bool kGuarding = MB2CO_CONFIG_GUARDING != 0;
/// Modbus FC 08 diagnostics (counters, return query data).
constexpr bool kDiagnostics = MB2CO_CONFIG_DIAGNOSTICS != 0;
/// The complex data-type descriptions 0020h-0023h.
constexpr bool kTypeDescriptions = MB2CO_CONFIG_TYPE_DESCRIPTIONS != 0;
/// 1011h restore default parameters.
constexpr bool kRestoreDefaults = MB2CO_CONFIG_RESTORE_DEFAULTS != 0;
/// SDO block transfer and domain objects (server and client).
constexpr bool kSdoBlock = MB2CO_CONFIG_SDO_BLOCK != 0;
/// TPDOs answer remote requests (transmission types 252/253 by RTR).
constexpr bool kTpdoRtr = MB2CO_CONFIG_TPDO_RTR != 0;
/// TPDOs the application names (Tpdos::set_profile_events) send with type
/// 255 on its event, not on a change of their data (the I/O node's CiA 401
/// interrupt masks); off, type 255 is change of data like 254.
constexpr bool kProfileEvents = MB2CO_CONFIG_PROFILE_EVENTS != 0;
/// The OD's wide extras: 64-bit limits, data types 0008h-001Bh, Modbus map
/// items wider than 32 bits, the gateway's example entries of 2500h.
constexpr bool kWideTypes = MB2CO_CONFIG_WIDE_TYPES != 0;
/// Requests from other framers than the RTU one (Modbus/TCP's MBAP) into
/// the one slave core, their deferred FC 2Bh/0Dh answers on their own
/// channel (mb2co-node --tcp).
constexpr bool kModbusTcp = MB2CO_CONFIG_MODBUS_TCP != 0;
/// The node hands its acceptance ranges to the CAN port's filters
/// (CanControl::set_filters). Off: the image receives every frame and
/// carries no code for filters (the network gateway: it hears every node's
/// SDO responses and heartbeats, more than the MCP2515's filters hold).
constexpr bool kAcceptanceFilters = MB2CO_CONFIG_ACCEPTANCE_FILTERS != 0;
/// TIME (CiA 301, 1012h) and the high-resolution time stamp 1013h: the
/// node's network clock, set by TIME frames and 1013h writes
/// (canopen/time_stamp.h). MB2CO_CONFIG_TIME 1: consumer; 2: the producer
/// too (1012h bit 30; its day state costs RAM the station has not).
constexpr bool kTime = MB2CO_CONFIG_TIME != 0;
constexpr bool kTimeProducer = MB2CO_CONFIG_TIME >= 2;
/// ObjectDictionary's hot reads (get(), copy_out() and set() of a numeric RAM
/// row, attr(), index_of(), sub_of(), a number's size) go through a table
/// resolved once at construction (canopen/od.h), not by placing the row and
/// decoding its type, and find() remembers its answers: the hot lookups of
/// the simulator and the Linux node. Hosts only (14 KB of RAM per dictionary).
constexpr bool kOdDirectGet = MB2CO_CONFIG_OD_DIRECT_GET != 0;

}  // namespace profile
}  // namespace mb2co

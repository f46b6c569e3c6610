// Profile "network": the Uno network gateway mb2co-gateway-network.elf: the station plus FC 2Bh/0Dh,
// without exactly guarding, FC 08, 0020h-0023h and 1011h (issue 23's decision; 1011h the last,
// left out after the design steps: docs/gateway-network.md, "Builds").
// One switch per service (1 in, 0 out); shared/profiles/profile.h says what
// each means and how code reads them.
#pragma once

#define MB2CO_PROFILE_NAME "network"
#define MB2CO_CONFIG_NETWORK 1             // FC 2Bh/0Dh to every node (CiA 309-2)
#define MB2CO_CONFIG_GUARDING 0            // node/life guarding, 100Ch/100Dh
#define MB2CO_CONFIG_DIAGNOSTICS 0         // Modbus FC 08
#define MB2CO_CONFIG_TYPE_DESCRIPTIONS 0   // OD 0020h-0023h
#define MB2CO_CONFIG_RESTORE_DEFAULTS 0    // OD 1011h (the budget demands it: -114 B, -4 B RAM)
#define MB2CO_CONFIG_SDO_BLOCK 0           // SDO block transfer, domains
#define MB2CO_CONFIG_TPDO_RTR 0            // TPDOs answer remote requests
#define MB2CO_CONFIG_PROFILE_EVENTS 0      // TPDO type 255 on the device profile's event (CiA 401)
#define MB2CO_CONFIG_WIDE_TYPES 0          // 64-bit types, 0008h-001Bh, 2500h
#define MB2CO_CONFIG_MODBUS_TCP 0          // Modbus/TCP channels into the slave
#define MB2CO_CONFIG_ACCEPTANCE_FILTERS 0  // CAN filters set from the acceptance ranges
#define MB2CO_CONFIG_OD_DIRECT_GET 0       // the OD's hot reads without decoding (14 KB RAM per OD)
#define MB2CO_CONFIG_TIME 0                // TIME (CiA 301), 1012h/1013h: 1 consumer, 2 + producer

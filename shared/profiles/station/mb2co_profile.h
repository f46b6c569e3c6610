// Profile "station": the Uno station image mb2co-gateway.elf: every service the line, the PC plant app
// and a master use; no FC 2Bh (its flash).
// One switch per service (1 in, 0 out); shared/profiles/profile.h says what
// each means and how code reads them.
#pragma once

#define MB2CO_PROFILE_NAME "station"
#define MB2CO_CONFIG_NETWORK 0             // FC 2Bh/0Dh to every node (CiA 309-2)
#define MB2CO_CONFIG_GUARDING 1            // node/life guarding, 100Ch/100Dh
#define MB2CO_CONFIG_DIAGNOSTICS 1         // Modbus FC 08
#define MB2CO_CONFIG_TYPE_DESCRIPTIONS 1   // OD 0020h-0023h
#define MB2CO_CONFIG_RESTORE_DEFAULTS 1    // OD 1011h
#define MB2CO_CONFIG_SDO_BLOCK 0           // SDO block transfer, domains
#define MB2CO_CONFIG_TPDO_RTR 0            // TPDOs answer remote requests
#define MB2CO_CONFIG_PROFILE_EVENTS 0      // TPDO type 255 on the device profile's event (CiA 401)
#define MB2CO_CONFIG_WIDE_TYPES 0          // 64-bit types, 0008h-001Bh, 2500h
#define MB2CO_CONFIG_MODBUS_TCP 0          // Modbus/TCP channels into the slave
#define MB2CO_CONFIG_ACCEPTANCE_FILTERS 1  // CAN filters set from the acceptance ranges
#define MB2CO_CONFIG_OD_DIRECT_GET 0       // the OD's hot reads without decoding (14 KB RAM per OD)
#define MB2CO_CONFIG_TIME 0  // TIME consumer, 1012h/1013h (1: +0.5 KB flash, docs/performance.md)

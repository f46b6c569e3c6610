// The one compile-time switch of Modbus/TCP in the slave (modbus/tcp_channel.h:
// requests that come through another framer than the RTU one). On for the
// host, where mb2co-node serves Modbus/TCP; off on the AVR, whose images have
// no network: there the slave compiles exactly as without it. Every
// translation unit of one image must see the same value (it changes
// SlaveCore's layout). The deferred answers it routes are FC 2Bh/0Dh's.
#pragma once

#include "modbus/net_switch.h"

#ifndef MB2CO_MODBUS_TCP
#ifdef __AVR__
#define MB2CO_MODBUS_TCP 0
#else
#define MB2CO_MODBUS_TCP 1
#endif
#endif

#if MB2CO_MODBUS_TCP && !MB2CO_GATEWAY_NET
#error "MB2CO_MODBUS_TCP routes FC 2Bh/0Dh's deferred answers: it needs MB2CO_GATEWAY_NET"
#endif

// The one compile-time switch of FC 2Bh / MEI 0Dh (the Modbus master's access
// to the whole CANopen network: modbus/network_pdu.h, gateway/network_service.h).
// On unless the build says otherwise; the Uno leaves it out by default (its
// flash), -DMB2CO_GATEWAY_NET=1 puts it in. Every translation unit of one
// image must see the same value (it changes SlaveCore's and Gateway's layout).
#pragma once

#ifndef MB2CO_GATEWAY_NET
#ifdef __AVR__
#define MB2CO_GATEWAY_NET 0
#else
#define MB2CO_GATEWAY_NET 1
#endif
#endif

// FC 2Bh / MEI 0Dh (the Modbus master's access to the whole CANopen network:
// modbus/network_pdu.h, gateway/network_service.h) is in an image when its
// profile says so (MB2CO_CONFIG_NETWORK, shared/profiles/profile.h).
#pragma once

#include "profiles/profile.h"

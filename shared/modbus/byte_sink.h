// Where a Modbus/RTU port sends bytes (modbus::ByteSink): declared with the
// rest of the platform contract in platform/device_port.h.
#pragma once
#include "platform/device_port.h"

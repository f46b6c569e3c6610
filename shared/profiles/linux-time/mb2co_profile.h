// Profile "linux-time": the linux profile with TIME (1012h consumer + producer, 1013h): the TIME
// service's tests build with it (tests/canopen/time). It becomes the linux profile once the
// programs' saved sets, filters and docs follow 1012h/1013h (docs/performance.md, TIME).
#pragma once

#include "../linux/mb2co_profile.h"

#undef MB2CO_PROFILE_NAME
#undef MB2CO_CONFIG_TIME
#define MB2CO_PROFILE_NAME "linux-time"
#define MB2CO_CONFIG_TIME 2  // TIME consumer + producer, 1012h/1013h

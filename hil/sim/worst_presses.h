// The operator of `mb2co-lab --scenario latency --worst`: instead of random
// press phases, a deterministic search of the phasings the analytical bound
// assumes (docs/timing.md §9, "Worst case searched"). Internal to hil/sim's
// scenarios.
#pragma once
#include <stdint.h>

#include "sim/line.h"
#include "sim/press_loop.h"
#include "sim/scenarios.h"

namespace mb2co {
namespace sim {

/// Presses START on `button_station` at phases of the PC's cycle chosen by
/// a grid search (coarse grid over one cycle, then a fine grid around the
/// worst phase found, each point pressed several times: the pass and PC
/// jitters differ at every repetition), then with the other stations
/// switched off and on so that their heartbeat and TPDO1 timer frames reach
/// the passes of the PC's poll (without `interference`) and those around
/// the press and the debounce's end, and measures press → lab LED on at
/// `led_station`. With `interference`, every other station's START or STOP
/// is pressed so that its TPDO1 is queued with the lab's PDOs (the critical
/// instant of the CAN analysis), and then every station's periodic frames
/// are placed at once: the PC's Arduino and the lab button's, which cannot
/// be switched off, by an NMT reset communication from the lab's NMT master,
/// a controller the search adds to line.bus(). Deterministic: the same line
/// gives the same samples. Takes over line.on_leds; the line must not run
/// on after it (the added controller is gone then).
PressRun search_worst_presses(Line& line, int button_station, int led_station, bool interference,
                              const Progress& progress);

}  // namespace sim
}  // namespace mb2co

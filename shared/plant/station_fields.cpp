#include "plant/station_fields.h"

#include "gateway/gateway_od.h"

namespace mb2co {
namespace plant {

namespace {
// Index, sub-index and width come from the OD's own entry keys (the names
// the firmware uses for the same entries); the names are the log's columns.
constexpr FieldSpec spec(canopen::OdKey key, const char* name) {
  return {key.index, key.sub, key.bits, name};
}
namespace e = gateway::od::GatewayEntry;
const FieldSpec kSpecs[kFieldCount] = {
    spec(e::x6000_1_readInput8Bit1, "inputs"),        spec(e::x2100_2_runState, "run_state"),
    spec(e::x2100_3_stop2Count, "stop2_count"),       spec(e::x2100_4_stopCause, "stop_cause"),
    spec(e::x2100_5_startCount, "start_count"),       spec(e::x2100_6_stopCount, "stop_count"),
    spec(e::x2110_1_prevRunState, "prev_run"),        spec(e::x2110_2_prevStop2Count, "prev_stop2"),
    spec(e::x2110_3_prevStatus, "prev_status"),       spec(e::x2120_1_nextRunState, "next_run"),
    spec(e::x2120_3_nextStatus, "next_status"),       spec(e::x2200_0_leds, "leds"),
    spec(e::x2300_1_buttonEdgeUs, "edge_us"),         spec(e::x2300_2_labLedUs, "led_us"),
    spec(e::x2300_3_remoteButtonsUs, "remote_us"),    spec(e::x2130_1_remoteButtons, "remote_buttons"),
    spec(e::x1001_0_errorRegister, "error_register"), spec(e::x2002_0_nmtState, "nmt_state"),
    spec(e::x2100_1_runCommand, "run_command"),       spec(e::x6200_1_writeOutput8Bit1, "lab_led"),
};
}  // namespace

const FieldSpec& field_spec(Field field) {
  return kSpecs[static_cast<int>(field)];
}

}  // namespace plant
}  // namespace mb2co

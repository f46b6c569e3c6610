#!/bin/bash
# ctest tests.registered: every area whose tests need a peer, a sandbox or a
# program from another folder registers them; a CMake condition that turns
# false (a target configured later, a tool not found) must not drop a whole
# area in silence. Usage: registered_tests.sh BUILD_DIR
set -u
list=$(ctest --test-dir "${1:?usage: registered_tests.sh BUILD_DIR}" -N)
missing=0
for name in vcan.socketcan_port node.ring node.network node.wide_types load.bus_flood uno.vcan uno.ionode_vcan master.network master.transfers master.configure \
            master.via_modbus uno.network uno.network_pymodbus uno.network_load \
            node.tcp_network master.via_modbus_tcp node.pymodbus_tcp pcapp.e2e.tcp_station pcapp.e2e.remote_latency_common_clock \
            master.serve master.serve_npm \
            node.trace_can node.ring_ids node.sdo_flood uno.student_line live.uno_chain3 master.bounds master.bursts master.bursts_calls \
            peers.npm_client_vs_node peers.npm_client_vs_npm_server peers.npm_listen_nmt_sync \
            timing.avr_compile.serial_segment \
            peers.master_vs_npm_server peers.block_by_hand labs.doc vcan.interactive_shell live.serial_operator \
            serialnet.avr_compile.serial_link cli.table_up_to_date cli.error_shapes docs.cli cli.install_tree \
            bridge.vcan_poll bridge.vcan_token bridge.vcan_echo bridge.uno_vcan peers.npm_client_vs_ionode docs.serial-canopen docs.mb2co-master docs.mb2co-node docs.examples \
            sim.image.SyncProcessing.RealImageAnswersEverySyncWithinTheBound sim.lab_plots_svg \
            canopen.time.Time.ConsumerSetsTheClockTo1013hAtTheFramesArrival \
            uno.UnoQuietLine.NoReceiveOverflowWhenNode2sTpdo1AndHeartbeatComeTogether; do
  if ! grep -qE "Test +#[0-9]+: ${name//./\\.}\$" <<<"$list"; then
    echo "not registered: $name" >&2
    missing=$((missing + 1))
  fi
done
total=$(grep -cE "Test +#[0-9]+:" <<<"$list")
echo "$total tests registered, $missing of the required ones missing"
exit $((missing > 0))

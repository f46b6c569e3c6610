#!/usr/bin/env python3
"""End-to-end: mb2co-plant --tcp runs a station over Modbus/TCP against
mb2co-node --can none --serial none --tcp (docs/mb2co-node.md "Modbus/TCP"),
with the pty scenarios' steps (e2e_plant.py): START runs it, STOP2 stops it,
SIGTERM leaves RUN=0; the node killed and started again on the same port:
plant safe, reconnected by itself. No serial line anywhere.

usage: e2e_plant_tcp.py --plant BIN --node BIN
"""
import argparse
import os
import re
import signal
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import e2e_plant as e2e  # noqa: E402  (the steps and the process helpers)


class TcpSetup(e2e.Setup):
    """The node serves Modbus/TCP only; the plant connects with --tcp."""

    def __init__(self, args):
        super().__init__(args)
        self.address = "127.0.0.1:0"  # the first node takes a free port, later ones the same

    def start_node(self):
        self.node = e2e.Proc("mb2co-node", [self.args.node, "--can", "none", "--serial", "none",
                                            "--tcp", self.address])
        e2e.PROCS.append(self.node)
        m = self.node.expect(r"^ready node=1 can=none serial=none tcp=(\S+)$", "node ready on TCP")
        self.address = m.group(1)
        return self.node

    def start_plant(self, *extra):
        plant = e2e.Proc("mb2co-plant", [self.args.plant, "--tcp", self.address, "--plain", *e2e.PLANT_TIMEOUT,
                                         *extra], stdin=False)
        e2e.PROCS.append(plant)
        plant.expect(r" link up tcp:" + re.escape(self.address) + r" slave 255: mb2co mb2co gateway .*Modbus/TCP$",
                     "first link up")
        plant.expect(r" buttons none$", "first read of the panel")
        return plant


def run(s):
    s.start_node()
    plant = s.start_plant("--reconnect-max-ms", "400")
    e2e.start_station(s, plant)
    e2e.click(s, plant, "STOP2", "stopped cause=local_stop2")
    s.node_run_led(False)
    e2e.start_station(s, plant)
    # The node gone and back on the same port: the plant is made safe and
    # reconnects without a restart; the new gateway is stopped until START.
    s.node.kill(signal.SIGKILL)
    plant.expect(r" link lost: .* plant safe, reconnecting$", "link loss is reported")
    plant.expect(r" state stopped cause=link_lost$", "link loss makes the station safe")
    s.start_node()
    plant.expect(r" link up tcp:" + re.escape(s.address), "reconnected without a restart")
    plant.expect(r" buttons none$", "first read of the new gateway's panel")
    run_state, _ = s.node_state().groups()
    e2e.check(run_state == "0", "the new gateway runs before a START")
    e2e.start_station(s, plant)
    rest = s.stop_plant(plant, signal.SIGTERM)
    e2e.check(not any("wire_us=" in line for line in rest), "a serial wire time in a Modbus/TCP summary")
    s.node_run_led(False)
    run_state, cause = s.node_state().groups()
    e2e.check(run_state == "0" and cause != "4", f"after SIGTERM: run={run_state} cause={cause}, want 0 and no "
                                                 "watchdog stop (4): the TCP requests fed it")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--plant", required=True)
    ap.add_argument("--node", required=True)
    s = TcpSetup(ap.parse_args())
    try:
        run(s)
    finally:
        s.cleanup()
    print("ok station over Modbus/TCP")


if __name__ == "__main__":
    main()

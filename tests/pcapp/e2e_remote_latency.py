#!/usr/bin/env python3
"""mb2co-plant latency --remote on the common clock (issue 25 item 1), on vcan0
(run inside hil/uml/run-with-vcan.sh): two mb2co-node stations in a chain,
mb2co-master time as the TIME producer.

1. Refused (exit 4, one line why) while no station's clock was set by TIME.
2. 1012h's consumer bit set on both by SDO, `mb2co-master time --period 200`:
   each node's 1013h, read by mb2co-master and by python3-can (an independent
   SDO client), agrees with the host clock: it lies between the host's clock
   before the request less 1 ms (TIME carries whole ms) and less the TIME
   frame's delivery (at most kDeliveryUs under user-mode Linux), and the
   host's clock after the answer.
3. Refused on station 1, the first of the chain (no previous station).
4. Presses on station 1 measured from station 2: from station 1's own edge
   stamp to station 2's LED stamp. Each delay includes the debounce (2000h/6,
   20 ms) before the PDO could leave station 1 (hop_us >= 20 ms) and comes
   after the PDO's arrival (delay >= hop); the uncertainty is printed.
5. Refused once station 1 is gone (unreachable: the gateway's SDO timeout).

usage: e2e_remote_latency.py --plant BIN --node BIN --master BIN
"""
import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
import time

import can

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from e2e_plant import PROCS, Proc, fail  # noqa: E402

CANOPEN_EPOCH_UNIX_S = 441763200  # 1984-01-01T00:00:00Z
DEBOUNCE_US = 20000  # 2000h/6 default
DELIVERY_US = 50000  # a TIME frame from the master's clock read to the node's stamp, user-mode Linux
PLANT_LINK = ("--timeout-ms", "500", "--retries", "3")


def host_network_us():
    """The host's clock on 1013h's scale: us since 1984-01-01 UTC mod 2^32."""
    return (time.time_ns() // 1000 - CANOPEN_EPOCH_UNIX_S * 1000000) % (1 << 32)


def signed32(v):
    v %= 1 << 32
    return v - (1 << 32) if v >= 1 << 31 else v


def run(argv, timeout=30):
    return subprocess.run(argv, capture_output=True, text=True, timeout=timeout)


class Line:
    def __init__(self, args, tmp):
        self.args = args
        self.tmp = tmp
        self.nodes = {}

    def start_node(self, node_id):
        tty = os.path.join(self.tmp, f"tty{node_id}")
        n = Proc(f"node{node_id}", [self.args.node, "--can", "vcan0", "--pty", tty, "--node-id", str(node_id),
                                    "--stations", "2", "--topology", "chain"])
        PROCS.append(n)
        n.expect(rf"^ready node={node_id} ", f"node {node_id} ready")
        n.tty = tty
        self.nodes[node_id] = n

    def master(self, *words, timeout=30):
        return run([self.args.master, "-i", "vcan0", *words], timeout)

    def plant(self, node_id, *extra, timeout=60):
        return run([self.args.plant, "latency", "--remote", "--port", self.nodes[node_id].tty, "--plain",
                    *PLANT_LINK, *extra], timeout)


def expect_refusal(r, says, what):
    if r.returncode != 4 or says not in r.stderr:
        fail(f"{what}: want exit 4 and '{says}', got {r.returncode}\nstdout: {r.stdout}\nstderr: {r.stderr}")
    lines = [l for l in r.stderr.splitlines() if l]
    if len(lines) != 1:
        fail(f"{what}: one line why, got {lines}")
    print(f"refused as expected ({what}): {lines[0]}")


def sdo_upload_1013(bus, node_id):
    """1013h by an expedited SDO upload of python3-can's own making; the host
    clock before the request and after the answer."""
    while bus.recv(timeout=0) is not None:
        pass
    before = host_network_us()
    bus.send(can.Message(arbitration_id=0x600 + node_id, data=[0x40, 0x13, 0x10, 0, 0, 0, 0, 0],
                         is_extended_id=False))
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline:
        m = bus.recv(timeout=1)
        if m is not None and m.arbitration_id == 0x580 + node_id and m.data[1:3] == bytes([0x13, 0x10]):
            after = host_network_us()
            # Expedited upload response: 43h (4 bytes indicated) or 42h (size not indicated).
            if m.data[0] not in (0x42, 0x43):
                fail(f"SDO upload of 1013h from node {node_id}: {m.data.hex()}")
            return int.from_bytes(m.data[4:8], "little"), before, after
    fail(f"node {node_id}: no SDO answer for 1013h")


def check_clock(value, before, after, who):
    # value in [before - 1 ms - delivery, after] (mod 2^32).
    early = signed32(before - value)
    late = signed32(value - after)
    print(f"{who}: 1013h={value} host before={before} after={after}: "
          f"behind the request by {early} us, past the answer by {late} us")
    if early > 1000 + DELIVERY_US or late > 0:
        fail(f"{who}: 1013h {value} not within [{before} - {1000 + DELIVERY_US}, {after}]")


def master_read_1013(line, node_id):
    before = host_network_us()
    r = line.master("read", str(node_id), "1013", "0", "u32")
    after = host_network_us()
    if r.returncode != 0:
        fail(f"mb2co-master read {node_id} 1013 0: {r.returncode} {r.stderr}")
    value = int(re.findall(r"(0x[0-9A-Fa-f]+|\d+)\s*$", r.stdout.strip())[0], 0)
    return value, before, after


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--plant", required=True)
    ap.add_argument("--node", required=True)
    ap.add_argument("--master", required=True)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        line = Line(args, tmp)
        line.start_node(1)
        line.start_node(2)

        expect_refusal(line.plant(2), "clock was never set by TIME", "no TIME yet")

        r = line.master("write", "1,2", "1012", "0", "u32", "0x80000100")
        if r.returncode != 0:
            fail(f"setting 1012h's consumer bit: {r.returncode} {r.stdout} {r.stderr}")
        producer = Proc("mb2co-master time",
                        [args.master, "-i", "vcan0", "time", "--period", "200", "--count", "3000"], stdin=False)
        PROCS.append(producer)
        producer.expect(r"^time 2 ", "two TIME frames sent")

        bus = can.Bus(interface="socketcan", channel="vcan0")
        try:
            for node_id in (1, 2):
                check_clock(*sdo_upload_1013(bus, node_id), f"node {node_id} by python3-can")
                check_clock(*master_read_1013(line, node_id), f"node {node_id} by mb2co-master read")
        finally:
            bus.shutdown()

        expect_refusal(line.plant(1), "first of its chain", "station 1")

        presses = 3
        plant = Proc("mb2co-plant", [args.plant, "latency", "--remote", "--port", line.nodes[2].tty, "--plain",
                                     *PLANT_LINK, "--presses", str(presses)], stdin=False)
        PROCS.append(plant)
        plant.expect(r"link up", "link up")
        plant.expect(r"remote button on station 1, LED here on station 2: common clock", "probe passed")
        measured = []
        for n in range(1, presses + 1):
            line.nodes[1].send("click START 200")
            m = plant.expect(rf"press {n} delay_us=(\d+) \+-(\d+) hop_us=(\d+)", f"press {n}")
            measured.append(tuple(int(g) for g in m.groups()))
            print(f"mb2co-plant: {plant.seen[-1]}")
            time.sleep(0.5)  # released and debounced before the next click: a new edge
        summary = plant.expect(r"presses=3 missed=\d+ clock=common\(TIME\) uncertainty_us<=(\d+)", "summary")
        print(f"mb2co-plant: {plant.seen[-1]}")
        code = plant.wait_exit()
        if code not in (0, 3):
            fail(f"mb2co-plant exit {code}: {plant.err}")
        for delay, uncertainty, hop in measured:
            print(f"press: delay {delay} us +-{uncertainty} us, of it edge -> PDO here {hop} us")
            if hop + uncertainty < DEBOUNCE_US:
                fail(f"edge to the PDO's arrival {hop} us: shorter than the debounce before it")
            if delay < hop:
                fail(f"delay {delay} us shorter than its own hop {hop} us")
            if uncertainty < 1000 or uncertainty > int(summary.group(1)):
                fail(f"uncertainty {uncertainty} us outside [1000, {summary.group(1)}]")

        line.nodes[1].send("quit")
        line.nodes[1].expect(r"^bye", "node 1 gone")
        expect_refusal(line.plant(2), "station 1 unreachable", "remote gone")
        for proc in PROCS:
            proc.kill(signal.SIGTERM)
    print("PASS")


if __name__ == "__main__":
    main()

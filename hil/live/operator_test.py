#!/usr/bin/python3
"""Test of the hardware run (run-line.sh --serial) without hardware: three
mb2co-node on vcan0 stand in for the Arduinos behind their ptys, and this
script plays the operator — it reads the run's '>>> press B at station ...'
lines and clicks B on those nodes' control channels, like a person with a
finger on the button (300 ms). It knows nothing else about the run.

usage: operator_test.py --node BIN --plant BIN [--stations N]
Exit 0 when the run passed with exactly the prompts of the stop2 scenario.
"""
import argparse
import os
import re
import shutil
import sys
import tempfile

from line_views import NodeView
from live_procs import Failure, Pump

PROMPT_RX = re.compile(r">>> press (START|STOP2) at station ([\d, ]+)$")
HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--node", required=True)
    p.add_argument("--plant", required=True)
    p.add_argument("--stations", type=int, default=3)
    a = p.parse_args()
    n = a.stations
    tmp = tempfile.mkdtemp(prefix="mb2co-live-operator-")
    pump = Pump()
    prompts = []
    try:
        nodes = {}
        for i in range(1, n + 1):
            view = NodeView(i)
            view.proc = pump.start(f"mb2co-node {i}", [a.node, "--can", "vcan0", "--node-id", str(i), "--stations",
                                                       str(n), "--topology", "ring", "--pty",
                                                       os.path.join(tmp, f"st{i}")], view.on_line, stdin=True)
            nodes[i] = view
        for i, view in nodes.items():
            pump.wait(lambda: view.ready is not None, f"node {i}: ready", 10)

        def on_run_line(text):
            m = PROMPT_RX.search(text)
            if m:
                stations = [int(s) for s in m.group(2).split(",")]
                prompts.append((m.group(1), stations))
                for i in stations:
                    # Like a hand: let go of whatever is still held on that
                    # panel (a STOP2 click may last longer than the run takes
                    # to ask for START), then click the asked-for button.
                    others = [b for b in ("START", "STOP", "STOP2") if b != m.group(1)]
                    nodes[i].proc.send("".join(f"release {b}\n" for b in others) + f"click {m.group(1)} 300\n")

        ports = ",".join(nodes[i].ready["link"] for i in range(1, n + 1))
        run = pump.start("run-line", ["/usr/bin/python3", os.path.join(HERE, "run_line.py"), "--serial", ports,
                                      "--plant", a.plant, "--timeout", "20"], on_run_line)
        code = pump.wait_exit(run, 120)
        for _, text in run.lines:
            print(text)
        for text in run.err:
            print(text, file=sys.stderr)
        if code != 0:
            raise Failure(f"run-line --serial exited {code}")
        want = [("START", list(range(1, n + 1))), ("STOP2", [1]), ("START", [1, 2])]
        if prompts != want:
            raise Failure(f"prompts {prompts}, want {want}")
        print("operator test: PASS")
        return 0
    except Failure as f:
        print(f"operator test: FAIL: {f}", file=sys.stderr)
        return 1
    finally:
        pump.kill_all()
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())

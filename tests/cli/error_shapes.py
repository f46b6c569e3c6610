#!/usr/bin/env python3
"""Every program says a usage error in the one shape of docs/cli.md.

For each program of tests/cli/cli_table.sh: a bad value, an unknown option
(and a near miss that gets "did you mean"), a missing value and, where the
program has required operands, a missing operand. Each must print nothing on
stdout, exactly one line on stderr in its documented shape, and exit 2
(run-with-vcan.sh: 125, as env and timeout do). A program that has no option
with a value (mb2co-serial-hub, mb2co-demo) has no bad or missing value to
give; the table says which cases each program has.

Usage: error_shapes.py BUILD_DIR SOURCE_DIR
"""
import os
import re
import subprocess
import sys

build, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])

# name, executable, the name it prints, the exit status of a usage error
PROGRAMS = {
    "mb2co-timing": ("pcapp/timing/mb2co-timing", "mb2co-timing", 2),
    "mb2co-lab": ("hil/lab/mb2co-lab", "mb2co-lab", 2),
    "mb2co-od": ("pcapp/odtool/mb2co-od", "mb2co-od", 2),
    "mb2co-uno": ("hil/uno/mb2co-uno", "mb2co-uno", 2),
    "mb2co-plant": ("pcapp/plant/mb2co-plant", "mb2co-plant", 2),
    "mb2co-master": ("pcapp/master/mb2co-master", "mb2co-master", 2),
    "mb2co-node": ("firmware/linux/node/mb2co-node", "mb2co-node", 2),
    "mb2co-bridge": ("firmware/linux/bridge/mb2co-bridge", "mb2co-bridge", 2),
    "mb2co-serial-io-node": ("firmware/linux/bridge/mb2co-serial-io-node", "mb2co-serial-io-node", 2),
    "mb2co-serial-hub": ("firmware/linux/bridge/mb2co-serial-hub", "mb2co-serial-hub", 2),
    "mb2co-demo": ("hil/demo/mb2co-demo", "mb2co-demo", 2),
    # A script: it calls itself run-with-vcan in every message ("try run-with-vcan.sh --help").
    "run-with-vcan.sh": (os.path.join(src, "hil/uml/run-with-vcan.sh"), "run-with-vcan", 125),
}

# The shapes of docs/cli.md ("Errors"), as regular expressions on the one line.
E = re.escape


def bad(option, value):
    """PROGRAM: [CMD: ]--x must be ..., got "VALUE"[; did you mean ...?]"""
    return rf"(\w+: )?{E(option)} must be .+, got \"{E(value)}\"(; did you mean \S+\?)?"


def unknown(word, command="", near=""):
    """PROGRAM: unknown option --x[, did you mean --y?] (try PROGRAM [CMD] --help)"""
    hint = rf", did you mean {E(near)}\?" if near else r"(, [^()]+)?"
    return rf"unknown option {E(word)}{hint} \(try {{prog}}{' ' + E(command) if command else ''} --help\)"


def needs_value(option):
    """PROGRAM: --x needs a value"""
    return rf"{E(option)} needs a value"


def missing_operand(command, operands):
    """PROGRAM: missing operand: [CMD ]OPERANDS (try PROGRAM [CMD] --help)"""
    words = f"{command} {operands}" if command else operands
    return rf"missing operand: {E(words)}.* \(try {{prog}}{' ' + E(command) if command else ''} --help\)"


# program, arguments, the expected shape
CASES = [
    ("mb2co-timing", ["frame", "--id", "x"], bad("--id", "x")),
    ("mb2co-timing", ["load", "--bitrate", "500"], bad("--bitrate", "500")),
    ("mb2co-timing", ["frame", "--bogus"], unknown("--bogus", "frame")),
    ("mb2co-timing", ["rta", "--bitrat", "500k"], unknown("--bitrat", "rta", "--bitrate")),
    ("mb2co-timing", ["frame", "--bitrate"], needs_value("--bitrate")),
    ("mb2co-timing", ["rta"], missing_operand("rta", "FILE.csv")),
    ("mb2co-lab", ["--stations", "0"], bad("--stations", "0")),
    ("mb2co-lab", ["--bogus"], unknown("--bogus")),
    ("mb2co-lab", ["--bitrate", "500k"], unknown("--bitrate", near="--bitrates")),
    ("mb2co-lab", ["--stations"], needs_value("--stations")),
    ("mb2co-od", ["--node", "plc"], bad("--node", "plc")),
    ("mb2co-od", ["--bogus"], unknown("--bogus")),
    ("mb2co-od", ["--nod", "ionode"], unknown("--nod", near="--node")),
    ("mb2co-od", ["--format"], needs_value("--format")),
    ("mb2co-uno", ["--image", "x"], bad("--image", "x")),
    ("mb2co-uno", ["--bogus"], unknown("--bogus")),
    ("mb2co-uno", ["--imgae", "ionode"], unknown("--imgae", near="--image")),
    ("mb2co-uno", ["--elf"], needs_value("--elf")),
    ("mb2co-plant", ["--cycle-ms", "0"], bad("--cycle-ms", "0")),
    ("mb2co-plant", ["--baud", "1234"], bad("--baud", "1234")),
    ("mb2co-plant", ["latency", "--button", "GO"], bad("--button", "GO")),
    ("mb2co-plant", ["--bogus"], unknown("--bogus")),
    ("mb2co-plant", ["--cycels", "3"], unknown("--cycels", near="--cycles")),
    ("mb2co-plant", ["--port"], needs_value("--port")),
    ("mb2co-master", ["-t", "x", "read", "1", "1000", "0"], bad("--timeout", "x")),
    ("mb2co-master", ["read", "x", "1000", "0"], bad("node id", "x")),
    ("mb2co-master", ["read", "2", "1G00", "0"], bad("index", "1G00")),
    ("mb2co-master", ["read", "--bogus", "1", "1000", "0"], unknown("--bogus", "read")),
    ("mb2co-master", ["--interfac", "vcan0", "scan"], unknown("--interfac", near="--interface")),
    ("mb2co-master", ["upload", "--blok", "1", "1F50", "1", "f"], unknown("--blok", "upload", "--block")),
    ("mb2co-master", ["-i"], needs_value("--interface")),
    ("mb2co-master", ["scan", "-t"], needs_value("--timeout")),
    ("mb2co-master", ["read"], missing_operand("read", "NODE INDEX SUB")),
    ("mb2co-master", ["nmt", "start"], missing_operand("nmt", "start|stop")),
    ("mb2co-node", ["--node-id", "0"], bad("--node-id", "0")),
    ("mb2co-node", ["--bitrate", "500"], bad("--bitrate", "500")),
    ("mb2co-node", ["--bogus"], unknown("--bogus")),
    ("mb2co-node", ["--node-i", "3"], unknown("--node-i", near="--node-id")),
    ("mb2co-node", ["--can"], needs_value("--can")),
    ("mb2co-bridge", ["--bits", "9"], bad("--bits", "9")),
    ("mb2co-bridge", ["--bogus"], unknown("--bogus")),
    ("mb2co-bridge", ["--acces", "poll"], unknown("--acces", near="--access")),
    ("mb2co-bridge", ["--serial"], needs_value("--serial")),
    ("mb2co-serial-io-node", ["--node-id", "0"], bad("--node-id", "0")),
    ("mb2co-serial-io-node", ["--bogus"], unknown("--bogus")),
    ("mb2co-serial-io-node", ["--heartbeat", "100"], unknown("--heartbeat", near="--heartbeat-ms")),
    ("mb2co-serial-io-node", ["--serial"], needs_value("--serial")),
    ("mb2co-serial-hub", ["--bogus"], unknown("--bogus")),
    ("mb2co-serial-hub", ["--hlep"], unknown("--hlep", near="--help")),
    ("mb2co-serial-hub", [], missing_operand("", "MEMBER MEMBER")),
    ("mb2co-serial-hub", ["only-one"], missing_operand("", "MEMBER MEMBER")),
    ("mb2co-demo", ["--bogus"], unknown("--bogus")),
    ("mb2co-demo", ["--versoin"], unknown("--versoin", near="--version")),
    ("run-with-vcan.sh", ["--mode", "x", "--", "true"], bad("--mode", "x")),
    ("run-with-vcan.sh", ["--bogus"], unknown("--bogus")),
    ("run-with-vcan.sh", ["--mode"], needs_value("--mode")),
    ("run-with-vcan.sh", [], missing_operand("", "-- COMMAND")),
]

failures = 0
seen = set()
for name, args, shape in CASES:
    exe, prog, status = PROGRAMS[name]
    seen.add(name)
    path = exe if os.path.isabs(exe) else os.path.join(build, exe)
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    r = subprocess.run([path] + args, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=20,
                       env=env)
    pattern = rf"{E(prog)}: " + shape.replace("{prog}", E(os.path.basename(exe)))
    lines = r.stderr.split("\n")
    problems = []
    if r.returncode != status:
        problems.append(f"exit {r.returncode}, want {status}")
    if r.stdout:
        problems.append(f"stdout not empty: {r.stdout[:200]!r}")
    if len(lines) != 2 or lines[1] != "":
        problems.append(f"stderr is not one line: {r.stderr[:400]!r}")
    elif not re.fullmatch(pattern, lines[0]):
        problems.append(f"stderr {lines[0]!r} is not /{pattern}/")
    if problems:
        failures += 1
        print(f"FAIL {name} {' '.join(args)}: " + "; ".join(problems))
    else:
        print(f"ok   {name} {' '.join(args)}: {lines[0]}")

for name in PROGRAMS:
    if name not in seen:
        failures += 1
        print(f"FAIL {name}: no case")
table = open(os.path.join(src, "tests/cli/cli_table.sh")).read()
for listed in re.findall(r'^  "([^|]+)\|', table, re.M):
    if listed not in PROGRAMS:
        failures += 1
        print(f"FAIL {listed}: in cli_table.sh but not here")
print(f"{len(CASES) - failures} of {len(CASES)} error lines in the shape of docs/cli.md")
sys.exit(1 if failures else 0)

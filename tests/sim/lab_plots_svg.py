#!/usr/bin/env python3
"""mb2co-lab writes a histogram SVG per case for sync-roundtrip, sync-latency,
sync-processing and alternative (as for latency), and events.csv only with
--events.

Each SVG is parsed as XML: every panel has bars (rects in the plot area) and
red bound lines standing where the bound's value falls on the panel's value
axis (read from its tick labels), the bound taken from the run's own CSV or
report, not from the SVG.

Usage: lab_plots_svg.py MB2CO_LAB GATEWAY_ELF OUT_DIR
"""
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

NS = "{http://www.w3.org/2000/svg}"
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL: " + what)


def run(lab, out, *args):
    shutil.rmtree(out, ignore_errors=True)
    p = subprocess.run([lab, "--quiet", "--out", out, *args], capture_output=True, text=True)
    check(p.returncode == 0, "%s exits 0 (got %d: %s)" % (" ".join(args), p.returncode, p.stderr.strip()))
    return p.stdout


def panels(path):
    """Per panel (top to bottom): bars, red line x positions, x tick (x, value) pairs."""
    root = ET.parse(path).getroot()
    out = []
    for el in root:
        tag = el.tag.replace(NS, "")
        if tag == "text" and re.match(r".*: n=\d+, min ", el.text or ""):
            out.append({"bars": 0, "red": [], "ticks": []})
        if not out:
            continue
        p = out[-1]
        if tag == "rect" and el.get("fill") not in (None, "white"):
            p["bars"] += 1
        elif tag == "line" and el.get("stroke") == "red":
            check(el.get("x1") == el.get("x2"), "%s: a bound line is vertical" % path)
            p["red"].append(float(el.get("x1")))
        elif tag == "text" and el.get("text-anchor") == "middle" and re.fullmatch(r"[0-9.]+", el.text or ""):
            p["ticks"].append((float(el.get("x")), float(el.text)))
    return out


def x_of(panel, value):
    (x0, v0), (x1, v1) = panel["ticks"][0], panel["ticks"][-1]
    return x0 + (x1 - x0) * (value - v0) / (v1 - v0)


def check_svg(path, bounds):
    """bounds: per panel the bound values (in the axis unit) whose lines must be drawn."""
    check(os.path.exists(path), "%s written" % path)
    if not os.path.exists(path):
        return
    ps = panels(path)
    check(len(ps) == len(bounds), "%s: %d panels (got %d)" % (path, len(bounds), len(ps)))
    for k, (p, want) in enumerate(zip(ps, bounds)):
        check(p["bars"] > 0, "%s panel %d: bars drawn" % (path, k))
        check(len(p["red"]) == len(want), "%s panel %d: %d bound lines (got %d)" % (path, k, len(want), len(p["red"])))
        for x, v in zip(p["red"], want):
            # SVG coordinates have one decimal: within 0.1 px of the value's place.
            check(abs(x - x_of(p, v)) <= 0.11, "%s panel %d: bound %.2f at x %.1f (axis puts it at %.2f)"
                  % (path, k, v, x, x_of(p, v)))


def csv_bounds(path, unit_ns):
    """bitrate -> (best, worst) in the axis unit, from a sync CSV."""
    out = {}
    with open(path) as f:
        next(f)
        for line in f:
            rate, _, _, best, worst, _ = line.strip().split(",")
            out[int(rate)] = (int(best) / unit_ns, int(worst) / unit_ns)
    return out


def main():
    lab, elf, root = sys.argv[1:4]
    rates = ["125k", "1M"]
    kbit = [125, 1000]
    for scenario, count, unit_ns in (("sync-roundtrip", ["--syncs", "200"], 1e3),
                                     ("sync-latency", ["--presses", "100"], 1e6)):
        out = os.path.join(root, scenario)
        run(lab, out, "--scenario", scenario, "--bitrates", ",".join(rates), *count)
        b = csv_bounds(os.path.join(out, scenario + ".csv"), unit_ns)
        for r in kbit:
            check_svg(os.path.join(out, "%s-%dk.svg" % (scenario, r)), [list(b[r])])
        check(not os.path.exists(os.path.join(out, "events.csv")), scenario + ": no events.csv without --events")

    out = os.path.join(root, "alternative")
    report = run(lab, out, "--scenario", "alternative", "--bitrates", "125k", "--presses", "100")
    # Rows "   125k  pc modbus   n min mean max | best worst | ...": the bounds in ms.
    rows = re.findall(r"^\s+125k\s+(pc modbus|pc modbus\+canopen|arduino canopen)\s+\d+\s+[\d.]+\s+[\d.]+\s+[\d.]+"
                      r"\s+\|\s+([\d.]+)\s+([\d.]+)", report, re.M)
    check(len(rows) == 3, "alternative: three rows with bounds in the report (got %d)" % len(rows))
    check_svg(os.path.join(out, "alternative-125k.svg"), [[float(b), float(w)] for _, b, w in rows])

    out = os.path.join(root, "sync-processing")
    report = run(lab, out, "--scenario", "sync-processing", "--syncs", "50", "--elf", elf)
    m = re.search(r"^\s+us\s+\d+\s+[\d.]+\s+[\d.]+\s+[\d.]+\s+\|\s+(\d+)$", report, re.M)
    check(m is not None, "sync-processing: the bound in us in the report")
    if m:
        check_svg(os.path.join(out, "sync-processing.svg"), [[float(m.group(1))]])

    # --events: events.csv is written (and named in the report), with its header.
    out = os.path.join(root, "events")
    report = run(lab, out, "--scenario", "sync-roundtrip", "--bitrates", "1M", "--syncs", "20", "--events")
    path = os.path.join(out, "events.csv")
    check(os.path.exists(path), "--events writes events.csv")
    if os.path.exists(path):
        with open(path) as f:
            check(f.readline() == "t_ns,run,station,event,detail\n", "events.csv starts with its header")
            check(sum(1 for _ in f) > 100, "events.csv holds the run's events")
    check(" events.csv" in report, "the report names events.csv with --events")
    report = run(lab, os.path.join(root, "no-events"), "--scenario", "sync-roundtrip", "--bitrates", "1M",
                 "--syncs", "20")
    check(" events.csv" not in report, "the report does not name events.csv without --events")

    if failures:
        print("%d check(s) failed" % len(failures))
        return 1
    print("SVGs of sync-roundtrip, sync-latency, alternative, sync-processing with their bounds; "
          "events.csv only with --events: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())

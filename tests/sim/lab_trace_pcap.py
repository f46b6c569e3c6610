#!/usr/bin/env python3
"""mb2co-lab --trace FILE.pcap: the same runs (same seed) traced once as a
candump -L log and once as pcap hold the same frames at the same times. The
pcap is read here by the layout of pcap-savefile(5) and LINKTYPE_CAN_SOCKETCAN
(can_id big-endian with the flags of linux/can.h, len, 3 bytes, 8 data bytes),
not by the writer's code. Usage: lab_trace_pcap.py MB2CO_LAB WORK_DIR"""
import os
import re
import shutil
import struct
import subprocess
import sys

LINE = re.compile(r"^\((\d+)\.(\d{6})\) can0 ([0-9A-F]{3}|[0-9A-F]{8})#((?:[0-9A-F]{2}){0,8})$")


def run_lab(lab, work, trace):
    subprocess.run([lab, "--scenario", "stop2", "--quiet", "--out", os.path.join(work, "out"), "--trace", trace],
                   check=True, stdout=subprocess.DEVNULL)


def log_frames(path):
    frames = []
    with open(path) as f:
        for line in f:
            m = LINE.match(line.rstrip("\n"))
            if not m:
                sys.exit(f"not a candump -L line: {line!r}")
            frames.append((int(m[1]) * 1000000 + int(m[2]), f"{m[3]}#{m[4]}"))
    return frames


def pcap_frames(path):
    data = open(path, "rb").read()
    magic, major, minor, _zone, _sigfigs, _snaplen, linktype = struct.unpack_from("<IHHiIII", data, 0)
    if (magic, major, minor, linktype) != (0xA1B2C3D4, 2, 4, 227):
        sys.exit(f"pcap header: magic {magic:08x} version {major}.{minor} link type {linktype}")
    frames, at = [], 24
    while at < len(data):
        sec, usec, stored, wire = struct.unpack_from("<IIII", data, at)
        if stored != 16 or wire != 16 or usec >= 1000000 or at + 16 + stored > len(data):
            sys.exit(f"record at byte {at}: {stored}/{wire} bytes, usec {usec}")
        can_id, length = struct.unpack_from(">IB", data, at + 16)
        payload = data[at + 24:at + 24 + length]
        if length > 8 or can_id & 0x40000000:
            sys.exit(f"record at byte {at}: len {length}, can_id {can_id:08x}")
        ident = f"{can_id & 0x1FFFFFFF:08X}" if can_id & 0x80000000 else f"{can_id:03X}"
        frames.append((sec * 1000000 + usec, ident + "#" + payload.hex().upper()))
        at += 16 + stored
    return frames


def main():
    lab, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    run_lab(lab, work, os.path.join(work, "trace.log"))
    run_lab(lab, work, os.path.join(work, "trace.pcap"))
    text, pcap = log_frames(os.path.join(work, "trace.log")), pcap_frames(os.path.join(work, "trace.pcap"))
    if len(text) < 100:
        sys.exit(f"the log has only {len(text)} frames")
    if text != pcap:
        diff = next(i for i in range(min(len(text), len(pcap)) + 1) if i >= min(len(text), len(pcap)) or text[i] != pcap[i])
        sys.exit(f"{len(text)} frames in the log, {len(pcap)} in the pcap; first difference at frame {diff}")
    print(f"lab_trace_pcap: {len(pcap)} frames, the pcap and the candump log agree (time, id, data)")


main()

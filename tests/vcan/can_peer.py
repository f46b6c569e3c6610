#!/usr/bin/python3
"""An independent CAN peer for tests/vcan: python-can on SocketCAN.

Usage: can_peer.py IFACE
Prints READY once its socket is bound (every frame on IFACE from then on is
kept), then obeys one command per line on stdin:
  send FRAME...   send the frames in order, then print "SENT n"
  recv N          print "FRAME f" for each of the next N frames, then "DONE"
                  ("TIMEOUT" instead when none comes for 20 s)
  quit
Frames are written as candump -L/cansend do: 123#11223344, 01234567#, 7FF#R, 123#R8.
"""
import sys

import can


def parse_frame(text):
    ident, _, payload = text.partition("#")
    extended = len(ident) == 8
    if payload.startswith("R"):
        dlc = int(payload[1:]) if len(payload) > 1 else 0
        return can.Message(arbitration_id=int(ident, 16), is_extended_id=extended,
                           is_remote_frame=True, dlc=dlc)
    return can.Message(arbitration_id=int(ident, 16), is_extended_id=extended,
                       data=bytes.fromhex(payload))


def format_frame(msg):
    ident = ("%08X" if msg.is_extended_id else "%03X") % msg.arbitration_id
    if msg.is_remote_frame:
        return ident + "#R" + (str(msg.dlc) if msg.dlc else "")
    return ident + "#" + bytes(msg.data[:msg.dlc]).hex().upper()


def main():
    if len(sys.argv) != 2:
        print("usage: can_peer.py IFACE", file=sys.stderr)
        return 2
    bus = can.Bus(channel=sys.argv[1], interface="socketcan")
    print("READY", flush=True)
    for line in sys.stdin:
        words = line.split()
        if not words:
            continue
        if words[0] == "send":
            for text in words[1:]:
                bus.send(parse_frame(text))
            print("SENT %d" % (len(words) - 1), flush=True)
        elif words[0] == "recv":
            for _ in range(int(words[1])):
                msg = bus.recv(timeout=20)
                if msg is None:
                    print("TIMEOUT", flush=True)
                    break
                print("FRAME " + format_frame(msg), flush=True)
            print("DONE", flush=True)
        elif words[0] == "quit":
            break
        else:
            print("unknown command: " + words[0], file=sys.stderr)
            return 2
    bus.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())

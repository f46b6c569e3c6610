#!/usr/bin/python3
"""Requests per second through mb2co-master serve, measured by a client
that is not ours (Python's sockets): COUNT requests "[SEQ] NODE REQUEST",
the nodes taken in turn, at most WINDOW sent and not yet answered (1: each
waits for the answer before it; more: pipelined, as serve allows). Every
answer must be "[SEQ] VALUE" for its own SEQ, in order, and no ERROR.

usage: bench_serve.py ADDRESS FIRST_NODE LAST_NODE COUNT WINDOW [REQUEST]
prints: nodes=K window=W requests=N seconds=S rate=R/s
"""
import socket
import sys
import time


def connect(address):
    if address.startswith("unix:"):
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        s.connect(address[5:])
        return s
    host, _, port = address[4:].rpartition(":")
    s = socket.create_connection((host or "127.0.0.1", int(port)))
    s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return s


def main():
    if len(sys.argv) not in (6, 7):
        raise SystemExit(__doc__)
    address, first, last, count, window = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
    request = sys.argv[6] if len(sys.argv) == 7 else "read 0x1017 0 u16"
    nodes = list(range(first, last + 1))
    sock = connect(address)
    pending = b""
    sent = answered = 0
    start = time.monotonic()
    while answered < count:
        burst = []
        while sent < count and sent - answered < window:
            sent += 1
            burst.append("[%d] %d %s\n" % (sent, nodes[(sent - 1) % len(nodes)], request))
        if burst:
            sock.sendall("".join(burst).encode())
        chunk = sock.recv(65536)
        if not chunk:
            raise SystemExit("bench: the server closed after %d answers" % answered)
        pending += chunk
        while b"\r\n" in pending:
            line, pending = pending.split(b"\r\n", 1)
            answered += 1
            head = b"[%d] " % answered
            if not line.startswith(head) or b"ERROR" in line:
                raise SystemExit("bench: answer %d is %r" % (answered, line))
    seconds = time.monotonic() - start
    print("nodes=%d window=%d requests=%d seconds=%.3f rate=%.0f/s" % (len(nodes), window, count, seconds, count / seconds))


if __name__ == "__main__":
    main()

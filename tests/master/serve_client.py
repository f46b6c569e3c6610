#!/usr/bin/python3
"""A CiA 309-3 client that is not ours: Python's own sockets, nothing of
mb2co. It relays lines like nc does, so a test drives it line by line.

usage: serve_client.py unix:PATH|tcp:HOST:PORT

stdin, one directive per line:
  TEXT          sent as it is, followed by LF
  !raw HEX      the bytes HEX (pairs of hex digits), nothing added: binary
                garbage, a half line, CR LF endings
  !repeat N TEXT   TEXT followed by LF, N times in one send
  !long N TEXT  TEXT, N bytes "A", LF: one line of any length
  !shutdown     shutdown(SHUT_WR): end of input for the server, answers still read
  !close        close the socket and exit 0
stdout: "connected" once connected, then every line the server sends (its
CR LF or LF removed; bytes that are not UTF-8 as \\xNN), "eof" when the
server closed the connection. Exit 0; 1 when it cannot connect.
"""
import socket
import sys
import threading


def connect(address):
    if address.startswith("unix:"):
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        s.connect(address[5:])
        return s
    if address.startswith("tcp:"):
        host, _, port = address[4:].rpartition(":")
        return socket.create_connection((host.strip("[]") or "127.0.0.1", int(port)))
    raise SystemExit("usage: serve_client.py unix:PATH|tcp:HOST:PORT")


def reader(sock):
    pending = b""
    while True:
        try:
            chunk = sock.recv(65536)
        except OSError:
            chunk = b""
        if not chunk:
            break
        pending += chunk
        while b"\n" in pending:
            line, pending = pending.split(b"\n", 1)
            if line.endswith(b"\r"):
                line = line[:-1]
            print(line.decode("utf-8", "backslashreplace"), flush=True)
    if pending:
        print(pending.decode("utf-8", "backslashreplace"), flush=True)
    print("eof", flush=True)


def main():
    if len(sys.argv) != 2:
        raise SystemExit("usage: serve_client.py unix:PATH|tcp:HOST:PORT")
    try:
        sock = connect(sys.argv[1])
    except OSError as e:
        print("cannot connect: %s" % e, file=sys.stderr)
        return 1
    print("connected", flush=True)
    thread = threading.Thread(target=reader, args=(sock,), daemon=True)
    thread.start()
    for line in sys.stdin:
        line = line.rstrip("\n")
        try:
            if line.startswith("!raw "):
                sock.sendall(bytes.fromhex(line[5:]))
            elif line.startswith("!long "):
                _, count, text = line.split(" ", 2)
                sock.sendall(text.encode() + b"A" * int(count) + b"\n")
            elif line.startswith("!repeat "):
                _, count, text = line.split(" ", 2)
                sock.sendall((text + "\n").encode() * int(count))
            elif line == "!shutdown":
                sock.shutdown(socket.SHUT_WR)
            elif line == "!close":
                sock.shutdown(socket.SHUT_RDWR)
                sock.close()
                return 0
            else:
                sock.sendall((line + "\n").encode())
        except OSError as e:
            print("send failed: %s" % e, file=sys.stderr)
    thread.join()
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""A multi-drop serial line out of pseudo-terminals, for tests: every byte one
member writes is read by all the others (not by itself), like RS-485 without
echo. Usage: serial_hub.py LINK... ; makes one pty per LINK (a symlink to its
slave side, in raw mode), prints "ready" and relays until SIGTERM/SIGINT.
The hub keeps every slave side open so that members may come and go."""
import os
import select
import signal
import sys
import tty


def main():
    links = sys.argv[1:]
    if len(links) < 2:
        sys.stderr.write("usage: serial_hub.py MEMBER MEMBER [MEMBER...] (MEMBER: LINK or @PATH)\n")
        return 2
    masters = []
    keep = []
    made = []
    echoing = set()
    for link in links:
        if link.startswith("+"):
            link = link[1:]
            echoing.add(len(masters))
        if link.startswith("@"):
            fd = os.open(link[1:], os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
            tty.setraw(fd)
            masters.append(fd)
            continue
        master, slave = os.openpty()
        tty.setraw(slave)
        tty.setraw(master)
        os.set_blocking(master, False)
        if os.path.islink(link):
            os.unlink(link)
        os.symlink(os.ttyname(slave), link)
        masters.append(master)
        keep.append(slave)
        made.append(link)
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    print("ready", flush=True)
    try:
        while not stop:
            try:
                readable, _, _ = select.select(masters, [], [], 0.2)
            except InterruptedError:
                continue
            for m in readable:
                try:
                    data = os.read(m, 4096)
                except (BlockingIOError, OSError):
                    continue
                for i, other in enumerate(masters):
                    if other != m or i in echoing:
                        try:
                            os.write(other, data)
                        except OSError:
                            pass  # a member's queue is full or closed: its bytes are lost, as on a line
    finally:
        for link in made:
            if os.path.islink(link):
                os.unlink(link)
    return 0


if __name__ == "__main__":
    sys.exit(main())

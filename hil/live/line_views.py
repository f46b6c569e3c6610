"""What a live run knows about each station: parsers for mb2co-node's control
channel and mb2co-plant's event lines (formats in docs/mb2co-node.md and
docs/mb2co-plant.md), and what the RUN LEDs of a line must show."""
import re

# mb2co-node's and mb2co-uno's (which adds the shield's CAN LED: canerr=).
LEDS_RX = re.compile(r"^leds self=(\d) prev=(\d|blink) next=(\d|blink) lab=(\d)(?: canerr=\d)? at_us=(\d+)$")
STATE_RX = re.compile(r"^state node=(\d+) nmt=(\d+) run=(\d+) cause=(\d+) stop2=(\d+) "
                      r"prev=(\d+):(\d+):(\d+) next=(\d+):(\d+):(\d+) at_us=(\d+)$")
READY_RX = re.compile(r"^ready node=(\d+) can=(\S+) serial=(\S+)(?: link=(\S+))?$")
PLANT_RX = re.compile(r"^\s*\d+\.\d+ (.*)$")

# Stop causes of 2100h/4 (shared/gateway/line_app.h).
CAUSE_STOP2_HERE = 2
CAUSE_STOP2_PREVIOUS = 3
# Neighbour status of 2110h/3, 2120h/3.
STATUS_ALIVE = 1
STATUS_NONE = 2
# LED bits of 2200h (the plant's log column `leds`).
LED_SELF, LED_PREV, LED_NEXT = 1, 2, 4


def neighbours(i, n, ring):
    """(previous, next) station of station i in 1..n; None at a chain's end."""
    prev = i - 1 if i > 1 else (n if ring else None)
    nxt = i + 1 if i < n else (1 if ring else None)
    return (None if prev == i else prev), (None if nxt == i else nxt)


def expected_leds(i, n, ring, running):
    """(self, prev, next) LEDs of station i when the stations in `running` run."""
    prev, nxt = neighbours(i, n, ring)
    return (int(i in running), int(prev in running), int(nxt in running))


def led_bits(leds):
    self_, prev, nxt = leds
    return self_ * LED_SELF | prev * LED_PREV | nxt * LED_NEXT


def wrap_delta_us(later, earlier):
    """later - earlier on the nodes' 32-bit µs clocks (they wrap like micros())."""
    d = (later - earlier) & 0xFFFFFFFF
    return d - (1 << 32) if d >= 1 << 31 else d


class NodeView:
    """The station as its mb2co-node reports it: last LEDs, last state, every
    event in order (`events`: ('leds'|'state', dict)), the ready line."""

    def __init__(self, station):
        self.station = station
        self.proc = None
        self.ready = None
        self.leds = None
        self.state = None
        self.events = []

    def on_line(self, text):
        m = LEDS_RX.match(text)
        if m:
            # "blink": that neighbour is unknown (never equal to an expected 0/1).
            v = [x if x == "blink" else int(x) for x in m.groups()]
            self.leds = dict(self=v[0], prev=v[1], next=v[2], lab=v[3], at_us=v[4])
            self.events.append(("leds", self.leds))
            return
        m = STATE_RX.match(text)
        if m:
            # "blink": that neighbour is unknown (never equal to an expected 0/1).
            v = [x if x == "blink" else int(x) for x in m.groups()]
            self.state = dict(node=v[0], nmt=v[1], run=v[2], cause=v[3], stop2=v[4], prev=tuple(v[5:8]),
                              next=tuple(v[8:11]), at_us=v[11])
            self.events.append(("state", self.state))
            return
        m = READY_RX.match(text)
        if m:
            self.ready = dict(node=int(m.group(1)), can=m.group(2), serial=m.group(3), link=m.group(4))

    def first_event_since(self, mark, pred):
        """The first event (kind, fields) after index `mark` for which pred holds."""
        for kind, fields in self.events[mark:]:
            if pred(kind, fields):
                return kind, fields
        return None

    def replies_since(self, start):
        """Lines that answer commands (ok, error ..., bye), with their index."""
        return [(j, t) for j, (_, t) in enumerate(self.proc.lines[start:], start)
                if t == "ok" or t == "bye" or t.startswith("error")]


class PlantView:
    """The station as its mb2co-plant (--plain) reports it: event texts
    without the time column (`link up ...`, `buttons START`, `state moving`)."""

    def __init__(self, station):
        self.station = station
        self.proc = None
        self.events = []

    def on_line(self, text):
        m = PLANT_RX.match(text)
        if m:
            self.events.append(m.group(1))

    def seen_since(self, mark, pattern):
        rx = re.compile(pattern)
        return any(rx.search(e) for e in self.events[mark:])

    def last(self, prefix):
        """The last event starting with `prefix`, or None."""
        for e in reversed(self.events):
            if e.startswith(prefix):
                return e
        return None

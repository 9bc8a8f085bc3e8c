#!/usr/bin/python3
"""The live view of a run without a display (scripts/spy --text): every LCM channel heard on the
URL, its message rate, its last decoded values with units, and losses and repeats, refreshed once
a second. Pure Python (Debian's python3, no LCM C extension): it joins the UDP multicast group
itself and decodes with the project's generated types (scripts/rnav/lcmlog.py), so every channel
of the project is shown by field, and a foreign one by its size.

  scripts/spy --text [--lcm-url URL] [--netns-pid PID] [--duration S] [--json FILE]

Per channel: type, messages, rate [1/s] over the last second and mean/s, the rate between the
channel's first and last message (repeats not counted: the rate the run publishes at, however
late it started), bytes of the last message, and its scalar fields with their units from lcmtypes/*.lcm (a batch: its
element count and its last element's fields). Losses: gaps in each sender's LCM sequence numbers
(every message an lcm instance publishes, on any channel, carries the next number), per sender.
Repeats: a message whose bytes equal an earlier one's on the same channel (a lock-step resend),
and the clock's RESEND commands on SIM_WINDOW. LCM's packet formats (udpm): a short message is
one datagram 'LC02' seqno channel NUL payload; a long one is fragments 'LC03' seqno size offset
fragment_no n_fragments, the first carrying the channel. Times: each datagram's kernel arrival time
(SO_TIMESTAMP, the clock lcm-logger stamps its events with), so the view's own processing lag does
not move a channel's first and last message or its rate; the time of reading where the kernel gives
none. --duration S stops after S seconds (0:
until Ctrl-C) and --json FILE writes the final counts; the terminal view is redrawn in place on a
terminal, else a block of lines per second.
"""
import collections
import hashlib
import json
import os
import socket
import struct
import sys
import time
import urllib.parse

from rnav import cli_args
from rnav import lcmlog as rnav_lcmlog

PROG = "spy_text.py"
SHORT, FRAGMENT = 0x4C433032, 0x4C433033   # 'LC02', 'LC03'
DEFAULT_URL = "udpm://239.255.76.67:7667?ttl=0"
MAX_FIELDS = 6                              # fields shown per channel
MAX_TEXT = 40                               # characters shown of a text field
RESEND = 4                                  # sim_window_t.RESEND (lcmtypes/sim_window_t.lcm)
SO_TIMESTAMP = getattr(socket, "SO_TIMESTAMP", 29)  # Linux asm-generic/socket.h; SCM_TIMESTAMP equals it
TIMEVAL = struct.Struct("@ll")              # struct timeval: seconds, microseconds


def parse_url(url):
    """(group, port) of an udpm:// URL; ValueError naming what is wrong."""
    u = urllib.parse.urlparse(url)
    if u.scheme != "udpm":
        raise ValueError("only udpm:// URLs can be watched, got %r" % url)
    group, _, port = u.netloc.partition(":")
    socket.inet_aton(group)
    return group, int(port or 7667)


def listen(group, port):
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    if hasattr(socket, "SO_REUSEPORT"):
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
    s.bind(("", port))
    s.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, socket.inet_aton(group) + socket.inet_aton("0.0.0.0"))
    s.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMP, 1)
    s.settimeout(0.1)
    return s


def receive(sock):
    """(datagram, sender, arrival [s since the Unix epoch]): the kernel's arrival time of the
    datagram (SCM_TIMESTAMP), or the time of reading it where the kernel attached none."""
    data, ancillary, _, sender = sock.recvmsg(65536, socket.CMSG_SPACE(TIMEVAL.size))
    for level, kind, value in ancillary:
        if level == socket.SOL_SOCKET and kind == SO_TIMESTAMP and len(value) >= TIMEVAL.size:
            sec, usec = TIMEVAL.unpack_from(value)
            return data, sender, sec + usec * 1e-6
    return data, sender, time.time()


class Channel:
    def __init__(self):
        self.type, self.count, self.last_bytes, self.values = "?", 0, 0, ""
        self.times = collections.deque()
        self.repeats, self.seen = 0, set()
        self.first_unix = self.last_unix = None  # arrival of the first and last message [s since the Unix epoch]
        self.first_digest = self.last_digest = None  # BLAKE2b-128 of their payloads (to find them in a recorded log)

    def active_rate(self):
        """Messages other than repeats per second between this channel's first and last message's
        arrival (the rate the run publishes at, whenever it started), 0 with fewer than two."""
        n = self.count - self.repeats
        return (n - 1) / (self.last_unix - self.first_unix) if n >= 2 and self.last_unix > self.first_unix else 0.0


class View:
    def __init__(self, types, units):
        self.types, self.units = types, units
        self.channels = collections.OrderedDict()
        self.senders = {}            # (ip, port) -> [last seqno, messages, lost]
        self.fragments = {}          # (sender, seqno) -> [channel, size, {offset: bytes}, n]
        self.resend_commands = 0
        self.start = time.monotonic()
        self.start_unix = time.time()

    def packet(self, data, sender, now, arrival):
        """One datagram read at monotonic time `now` [s] that arrived at `arrival` [s since the Unix epoch]."""
        if len(data) < 8:
            return
        magic, seq = struct.unpack(">II", data[:8])
        if magic == SHORT:
            channel, _, payload = data[8:].partition(b"\0")
            self.message(channel.decode("utf-8", "replace"), payload, sender, seq, now, arrival)
        elif magic == FRAGMENT and len(data) >= 20:
            size, offset, number, n = struct.unpack(">IIHH", data[8:20])
            body = data[20:]
            key = (sender, seq)
            f = self.fragments.setdefault(key, [None, size, {}, n])
            if number == 0:
                channel, _, body = body.partition(b"\0")
                f[0] = channel.decode("utf-8", "replace")
            f[2][offset] = body
            if f[0] is not None and len(f[2]) == n:
                payload = b"".join(f[2][k] for k in sorted(f[2]))
                del self.fragments[key]
                if len(payload) == size:
                    self.message(f[0], payload, sender, seq, now, arrival)

    def message(self, name, payload, sender, seq, now, arrival):
        s = self.senders.setdefault(sender, [None, 0, 0])
        if s[0] is not None and seq > s[0] + 1:
            s[2] += seq - s[0] - 1
        s[0], s[1] = seq, s[1] + 1
        ch = self.channels.setdefault(name, Channel())
        ch.count += 1
        ch.last_bytes = len(payload)
        ch.times.append(now)
        if ch.first_unix is None:
            ch.first_unix = arrival
        ch.last_unix = arrival
        digest = hashlib.blake2b(payload, digest_size=16).digest()
        if ch.first_digest is None:
            ch.first_digest = digest
        ch.last_digest = digest
        if digest in ch.seen:
            ch.repeats += 1
        elif len(ch.seen) < 100000:
            ch.seen.add(digest)
        cls = self.types.get(payload[:8])
        if cls is None:
            ch.type, ch.values = "(not a project type)", ""
            return
        try:
            msg = cls.decode(payload)
        except Exception as e:  # a message that does not decode is shown as such, not dropped
            ch.type, ch.values = cls.__name__, "does not decode: %s" % e
            return
        ch.type = cls.__name__
        if ch.type == "sim_window_t" and getattr(msg, "command", None) == RESEND:
            self.resend_commands += 1
        ch.values = self.summary(msg)

    def summary(self, msg):
        """'field=value unit' for the message's scalar fields; a batch: n and its last element's."""
        cls = type(msg)
        parts = []
        items = [f for f in cls.__slots__ if isinstance(getattr(msg, f), list) and getattr(msg, f)
                 and hasattr(getattr(msg, f)[-1], "__slots__")]
        if items:
            parts.append("n=%d" % len(getattr(msg, items[0])))
            msg = getattr(msg, items[0])[-1]
            cls = type(msg)
        unit = self.units.get(cls.__name__, {})
        for f in cls.__slots__:
            v = getattr(msg, f)
            if isinstance(v, bool) or not isinstance(v, (int, float, str)):
                continue
            text = ("%.6g" % v) if isinstance(v, float) else str(v)
            if len(text) > MAX_TEXT:
                text = text[:MAX_TEXT] + "..."
            parts.append("%s=%s%s" % (f, text, " " + unit[f] if f in unit else ""))
            if len(parts) >= MAX_FIELDS:
                break
        return " ".join(parts)

    def rows(self, now):
        out = []
        for name, ch in self.channels.items():
            while ch.times and ch.times[0] < now - 1:
                ch.times.popleft()
            total = ch.count / max(now - self.start, 1e-9)
            out.append({"channel": name, "type": ch.type, "messages": ch.count, "rate_hz": len(ch.times),
                        "mean_rate_hz": total, "active_rate_hz": ch.active_rate(), "first_unix_s": ch.first_unix,
                        "last_unix_s": ch.last_unix, "first_blake2b": ch.first_digest.hex(),
                        "last_blake2b": ch.last_digest.hex(), "last_bytes": ch.last_bytes, "repeats": ch.repeats,
                        "last": ch.values})
        return out

    def text(self, now):
        rows = self.rows(now)
        lost = sum(s[2] for s in self.senders.values())
        head = "spy: %d channel(s), %d sender(s), %.0f s; lost %d (LCM sequence gaps), RESEND commands %d" % (
            len(rows), len(self.senders), now - self.start, lost, self.resend_commands)
        lines = [head, "%-22s %-26s %8s %7s %7s %7s  %s" % ("channel", "type", "messages", "rate/s", "mean/s", "repeats",
                                                           "last values")]
        for r in rows:
            lines.append("%-22s %-26s %8d %7d %7.1f %7d  %s" % (r["channel"][:22], r["type"][:26], r["messages"],
                                                               r["rate_hz"], r["active_rate_hz"], r["repeats"], r["last"]))
        return "\n".join(lines)

    def json(self, now):
        return {"seconds": now - self.start, "start_unix_s": self.start_unix, "channels": self.rows(now),
                "resend_commands": self.resend_commands,
                "senders": [{"sender": "%s:%d" % k, "messages": v[1], "lost": v[2]} for k, v in self.senders.items()]}


def main(argv):
    ap = cli_args.ArgumentParser(PROG, __doc__)
    ap.add_argument("--lcm-url", metavar="URL", default=os.environ.get("LCM_DEFAULT_URL", DEFAULT_URL),
                    help="LCM URL to listen on (udpm://GROUP:PORT)")
    ap.add_argument("--duration", metavar="S", type=float, default=0, help="stop after S seconds, >= 0 (0: until Ctrl-C)")
    ap.add_argument("--json", metavar="FILE", default=None, help="write the final counts as JSON to FILE")
    args = ap.parse_args(argv)
    if not (args.duration >= 0) or args.duration != args.duration or args.duration == float("inf"):
        ap.error("--duration must be finite and >= 0, got %r" % args.duration)
    try:
        group, port = parse_url(args.lcm_url)
    except (ValueError, OSError) as e:
        ap.error("--lcm-url: %s" % e)
    try:
        types = rnav_lcmlog.message_types()
    except Exception as e:
        sys.stderr.write("%s: error: the project's Python types: %s (run scripts/setup first)\n" % (PROG, e))
        return 1
    view = View(types, rnav_lcmlog.units())
    sock = listen(group, port)
    tty = sys.stdout.isatty()
    next_draw = time.monotonic() + 1
    try:
        while True:
            now = time.monotonic()
            if args.duration and now - view.start >= args.duration:
                break
            try:
                data, sender, arrival = receive(sock)
                view.packet(data, sender, time.monotonic(), arrival)
            except socket.timeout:
                pass
            if now >= next_draw:
                next_draw += 1
                sys.stdout.write(("\x1b[H\x1b[2J" if tty else "") + view.text(now) + "\n" + ("" if tty else "\n"))
                sys.stdout.flush()
    except KeyboardInterrupt:
        pass
    now = time.monotonic()
    sys.stdout.write(view.text(now) + "\n")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(view.json(now), f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

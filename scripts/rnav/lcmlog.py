"""The project's LCM event logs in Python: Debian's python3 (numpy for arrays), no LCM C extension.

    from rnav import lcmlog                          # (rnav.read_log wraps this module)
    t = lcmlog.tables("/tmp/run.lcmlog")             # {channel: {column: numpy array}}
    plots = t["PRL_APOI"]                            # one row per radar plot
    plots["range_m"], plots["utime"], plots["realization"]

Messages are decoded with the types `lcm-gen --python` writes into build/python/rnav at every
build (RNAV_BUILD names another build folder, RNAV_PYTHON_TYPES another folder holding the rnav
package), chosen by the fingerprint in each message's first 8 bytes. The generated modules join
this package (rnav.prl_plot_t ...): their folder is added to its search path.

Tables. A data channel gives one row per sample: a batch message (runner.wire=batch) a row per
element, carrying its header's window fields (realization, attempt, window, window_utime_begin,
window_utime_end); a sample message (runner.wire=sample) one row, with the fields of the window
SIM_WINDOW granted last (-1 if the log holds no grant). Fixed-size arrays become one column per
element (p_TA_L_0, p_TA_L_1, p_TA_L_2; P_0_0 ... P_3_3), variable-length arrays one text column
joined by ';'. Every row starts with log_event (the event number) and log_utime (when the
recorder received it [us since the Unix epoch]; `utime` is the sample's time of validity). The
control channels SIM_WINDOW, SIM_ACK and SIM_SCENARIO give one row per message, as logged. Units:
units() reads them from the comments of lcmtypes/*.lcm.

What is kept, as the C++ reader (estimators/diagnosis/io/lcm_log_streams) keeps it: of each realization
the last attempt (the clock repeats a realization that lost a message; all_attempts=True keeps
every attempt); of a message sent again (a lock-step resend) the first copy: a batch with the same
channel and window and the same bytes, a sample message with the same bytes in the same grant
(without a grant in the log, every sample message is a row: a copy cannot be told from a repeat).

Nothing is read silently wrong; LogError names the file, the byte offset or event, the channel:
  * every event is checked against the file before it is read (sync word 0xEDA1DA01, channel
    and data lengths within the file, event numbers increasing): a corrupt size never allocates;
  * every message must decode as the type its fingerprint names, using all its bytes; a
    fingerprint of no project type, or a channel changing type, is an error;
  * a batch that differs from an earlier one of the same window, a missing window or seq, a
    batch outside its grant's span, a realization whose last attempt did not complete (with
    SIM_WINDOW in the log), or a window whose samples differ in number from what the publisher's
    OK acknowledgement on SIM_ACK lists (when the log has acks) is an error.
"""

import csv
import collections
import json
import importlib
import os
import pkgutil
import re
import struct
import sys
from collections import namedtuple

SYNC = 0xEDA1DA01
_HEADER = struct.Struct(">Iqqii")  # sync, event number, receive utime [us], channel length, data length
MAX_CHANNEL_BYTES = 256            # LCM's limit is 63 (as estimators/diagnosis/io/lcm_event_reader.hpp)
CONTROL_CHANNELS = ("SIM_WINDOW", "SIM_ACK", "SIM_SCENARIO")
LOG_COLUMNS = ("log_event", "log_utime")
WINDOW_COLUMNS = ("realization", "attempt", "window", "window_utime_begin", "window_utime_end")
_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_START, _FINISH, _ABORT, _RESEND, _CLOSE = 1, 2, 3, 4, 6  # sim_window_t commands
_ACK_OK = 1                         # node_ack_t status


class LogError(Exception):
    """A log that is not what it claims: the message names the file and where."""


Event = namedtuple("Event", "offset number utime channel data")


def types_dir():
    """The folder holding the generated `rnav` package."""
    d = os.environ.get("RNAV_PYTHON_TYPES")
    if d:
        return d
    return os.path.join(os.environ.get("RNAV_BUILD", os.path.join(_ROOT, "build")), "python")


def message_types():
    """{8-byte fingerprint: class} of every project type (the generated rnav package)."""
    d = types_dir()
    if not os.path.isfile(os.path.join(d, "rnav", "__init__.py")):
        raise LogError("no generated Python types in %s (build the project: scripts/setup)" % d)
    # The generated modules import each other as rnav.NAME: they join this package.
    import rnav
    gen = os.path.join(d, "rnav")
    if gen not in rnav.__path__:
        rnav.__path__.append(gen)
    # As the generated __init__.py does: rnav.NAME is the class (their hashes call
    # rnav.batch_header_t._get_hash_recursive), set before any fingerprint is computed.
    classes = [getattr(importlib.import_module("rnav." + m.name), m.name) for m in pkgutil.iter_modules([gen])]
    for cls in classes:
        setattr(rnav, cls.__name__, cls)
    return {cls._get_packed_fingerprint(): cls for cls in classes}


def events(path):
    """Event(offset [bytes], number, receive utime [us], channel, data) of each event, checked."""
    size = os.path.getsize(path)
    with open(path, "rb") as f:
        off, ordinal, last = 0, 0, None
        while off < size:
            at = "%s: byte %d (event %d of the file)" % (path, off, ordinal)
            if size - off < _HEADER.size:
                raise LogError("%s: the file ends inside an event header (%d bytes left of %d): the log was cut"
                               % (at, size - off, _HEADER.size))
            sync, num, utime, clen, dlen = _HEADER.unpack(f.read(_HEADER.size))
            if sync != SYNC:
                raise LogError("%s: no sync word 0x%08X (found 0x%08X): corrupt, or not an LCM event log"
                               % (at, SYNC, sync))
            if not 0 < clen <= MAX_CHANNEL_BYTES:
                raise LogError("%s: channel name length %d outside [1, %d] (corrupt)" % (at, clen, MAX_CHANNEL_BYTES))
            if dlen < 0:
                raise LogError("%s: negative data length %d (corrupt)" % (at, dlen))
            need = _HEADER.size + clen + dlen
            if need > size - off:
                raise LogError("%s: claims %d bytes, the file has %d left: the log was cut or the sizes are corrupt"
                               % (at, need, size - off))
            if last is not None and num <= last:
                raise LogError("%s: event number %d after %d (they must increase; corrupt or spliced)"
                               % (at, num, last))
            try:
                channel = f.read(clen).decode("ascii")
            except UnicodeDecodeError:
                raise LogError("%s: the channel name is not ASCII (corrupt)" % at) from None
            yield Event(off, num, utime, channel, f.read(dlen))
            off, ordinal, last = off + need, ordinal + 1, num


def holds_close(path, run_id, start=0):
    """Whether the recording `path` from byte `start` on holds SIM_WINDOW CLOSE of run `run_id`.

    CLOSE is the clock's last message of a run that completed (lcmtypes/sim_window_t.lcm): the
    recorder reads one socket in arrival order and writes in that order, so once the CLOSE is in
    the file every message the run sent before it is too. The file may be one lcm-logger is still
    writing (its end cut inside an event), `start` a byte inside an event: only complete events
    are read, each found by its channel name and checked by its header (sync word, lengths) and
    its type's fingerprint."""
    with open(path, "rb") as f:
        f.seek(max(0, start))
        tail = f.read()
    name = b"SIM_WINDOW"
    cls = None
    at = tail.find(name)
    while at >= 0:
        head = at - _HEADER.size
        if head >= 0:
            sync, _, _, clen, dlen = _HEADER.unpack_from(tail, head)
            data = tail[at + clen:at + clen + dlen]
            if sync == SYNC and clen == len(name) and dlen > 8 and len(data) == dlen:
                if cls is None:
                    cls = {c.__name__: c for c in message_types().values()}["sim_window_t"]
                if data[:8] == cls._get_packed_fingerprint():
                    msg = cls.decode(data)
                    if msg.command == _CLOSE and msg.run_id == run_id:
                        return True
        at = tail.find(name, at + 1)
    return False


_PUBLISHED = re.compile(r"^[a-z_]+: published ((?:[A-Z0-9_]+=[0-9]+ ?)+)$")


def published_counts(logs_dir):
    """{channel: distinct messages published}, summed over the "NAME: published CHANNEL=N ..."
    lines the run's nodes write at exit into their logs (logs_dir/*.log; scripts/run's logs/)."""
    sent = collections.Counter()
    for name in sorted(os.listdir(logs_dir)):
        if name.endswith(".log"):
            with open(os.path.join(logs_dir, name), errors="replace") as f:
                for line in f:
                    m = _PUBLISHED.match(line.rstrip("\n"))
                    for kv in (m.group(1).split() if m else []):
                        channel, n = kv.rsplit("=", 1)
                        sent[channel] += int(n)
    return dict(sent)


def recording_shortfall(path, published):
    """The channels of which the LCM event log `path` holds fewer distinct messages than were
    published: [(channel, recorded, published)] in channel order, `published` a {channel: count}
    of the distinct messages the run's processes sent (a resend of the same bytes counts once;
    a recorder such as lcm-logger misses messages when its socket buffer overflows). Channels
    the log holds more of (another run's messages) are not listed."""
    seen = collections.defaultdict(set)
    for e in events(path):
        if e.channel in published:
            seen[e.channel].add(hash(e.data))
    return [(ch, len(seen[ch]), n) for ch, n in sorted(published.items()) if len(seen[ch]) < n]


def recording_warnings(path, logs_dir, why=""):
    """One line per channel the recording `path` lacks messages of (recording_shortfall against
    published_counts(logs_dir)), naming both counts; `why` ends each line (a likely cause)."""
    return ["run: warning: the LCM log holds %d of the %d distinct messages the nodes published on %s: "
            "lcm-logger missed %d%s" % (got, n, ch, n - got, why)
            for ch, got, n in recording_shortfall(path, published_counts(logs_dir))]


def decode(path, event, types):
    """The message of an event, as the project type its fingerprint names, else LogError."""
    cls = types.get(bytes(event.data[:8]))
    where = "%s: event %d (byte %d) on channel %s" % (path, event.number, event.offset, event.channel)
    if cls is None:
        raise LogError("%s: fingerprint %s is no project type (lcmtypes/*.lcm): a foreign message (read the "
                       "project's channels only: channels=, --channels), or corrupt"
                       % (where, bytes(event.data[:8]).hex()))
    try:
        msg = cls.decode(event.data)
        items = _batch_items(cls)
        if items and msg.n != len(getattr(msg, items)):
            raise ValueError("n = %d" % msg.n)
        if msg.encode() != event.data:
            raise ValueError("bytes left over")
    except Exception as e:  # the generated decoder raises struct.error, ValueError, ...
        raise LogError("%s does not decode as rnav.%s (%s: corrupt)" % (where, cls.__name__, e)) from None
    return msg


def _batch_items(cls):
    """The element array's name of a batch type (header, n, a variable-length array), else None."""
    s = cls.__slots__
    if len(s) == 3 and s[0] == "header" and s[1] == "n" and getattr(cls(), s[2]) == []:
        return s[2]
    return None


_COLUMNS = {}


def _columns(cls):
    """[(column, type name, field, element index or None, getter)] of a type's scalar columns."""
    if cls in _COLUMNS:
        return _COLUMNS[cls]
    out = []

    def walk(owner, field, name, value, get, index):
        if hasattr(value, "__slots__"):  # a nested structure: its fields, prefixed
            for f in value.__slots__:
                walk(type(value).__name__, f, name + "_" + f, getattr(value, f),
                     (lambda g, f: lambda m: getattr(g(m), f))(get, f), None)
        elif isinstance(value, list) and value:  # a fixed-size array: a column per element
            for i, v in enumerate(value):
                walk(owner, field, "%s_%d" % (name, i), v, (lambda g, i: lambda m: g(m)[i])(get, i),
                     (index or ()) + (i,))
        elif isinstance(value, list):  # a variable-length array (of numbers or strings): text
            out.append((name, owner, field, None, (lambda g: lambda m: _join(g(m), name))(get)))
        else:
            out.append((name, owner, field, index, get))

    default = cls()
    for f in cls.__slots__:
        walk(cls.__name__, f, f, getattr(default, f), (lambda f: lambda m: getattr(m, f))(f), None)
    _COLUMNS[cls] = out
    return out


def _join(values, name):
    """A variable-length array of numbers or strings as one text cell, ';' between elements."""
    if any(hasattr(x, "__slots__") for x in values):
        raise LogError("field %s: a variable-length array of structures, which a table does not flatten" % name)
    return ";".join(_text(x) for x in values)


def _text(x):
    """A value as CSV text: numbers in Python's shortest round-trip form, booleans as 1/0."""
    if isinstance(x, bool):
        return "1" if x else "0"
    if isinstance(x, float):
        return repr(x)
    return str(x)


class Table:
    """One channel: `columns` (names), `rows` (tuples of values), `type` (the rnav class)."""

    def __init__(self, columns, cls):
        self.columns, self.rows, self.type = list(columns), [], cls

    def arrays(self):
        """{column: numpy array}."""
        import numpy as np
        cols = list(zip(*self.rows)) if self.rows else [()] * len(self.columns)
        return {c: np.array(v) for c, v in zip(self.columns, cols)}


class _Chunk:
    """The rows one window of one channel contributes (a batch, or a grant's sample messages)."""

    def __init__(self, event, key, span, seq=None, data=None):
        self.event, self.key, self.span, self.seq, self.data = event, key, span, seq, data
        self.rows, self.seen = [], set()


def _one_run(path, runs, run_id, event):
    """Count a grant or batch of run `run_id` (event number `event`). A log of two runs (another
    run on the same network, or a log replayed while recording) mixes their realizations and
    windows: refused at the first message of a second run, naming the run ids (as the C++ reader
    does), before its windows can look like duplicates or gaps."""
    runs[run_id] = runs.get(run_id, 0) + 1
    if len(runs) > 1:
        raise LogError("%s: the log holds the traffic of 2 runs (run ids %s; the second from event %d): a log must "
                       "hold one run; record each run on its own network (scripts/run's default private namespace) "
                       "or its own --lcm-url" % (path, " and ".join(str(r) for r in runs), event))


def read(path, channels=None, all_attempts=False, types=None):
    """({channel: Table}, {channel: resent copies skipped}, {channel: rows of earlier attempts
    dropped}) of every channel of the log (or only `channels`), checked as the module says."""
    types = types if types is not None else message_types()
    grants = {}    # (realization, attempt) -> {window: (event number, sim_window_t)}, the first grant
    starts = {}    # realization -> event number of its last START or RESEND
    finish, abort = -1, ""
    acks = {}      # (realization, attempt, channel) -> {window: samples its publisher's OK ack lists}
    current = None  # the last grant (sim_window_t), the window of sample messages
    kinds, chunks, out, copies = {}, {}, {}, {}
    runs = {}      # run id -> grants and batches carrying it (one log, one run: see _one_run)
    n_events = 0
    for ev in events(path):
        n_events += 1
        ch = ev.channel
        if ch == "LCM_SELF_TEST":  # lcm's own start-up message
            continue
        wanted = channels is None or ch in channels
        if not wanted and ch not in ("SIM_WINDOW", "SIM_ACK"):
            continue
        msg = decode(path, ev, types)
        first = kinds.setdefault(ch, (type(msg), ev.number))
        if first[0] is not type(msg):
            raise LogError("%s: event %d on channel %s is rnav.%s, but event %d on it was rnav.%s (one type per "
                           "channel)" % (path, ev.number, ch, type(msg).__name__, first[1], first[0].__name__))
        if ch == "SIM_WINDOW":
            if msg.command in (_START, _RESEND):
                _one_run(path, runs, msg.run_id, ev.number)
                grants.setdefault((msg.realization, msg.attempt), {}).setdefault(msg.window, (ev.number, msg))
                starts[msg.realization] = ev.number
                current = msg
            elif msg.command == _FINISH:
                finish = ev.number
            elif msg.command == _ABORT:
                abort = msg.reason
        elif ch == "SIM_ACK" and msg.status == _ACK_OK:
            for c, n in zip(msg.published, msg.published_n):
                acks.setdefault((msg.realization, msg.attempt, c), {})[msg.window] = n
        if not wanted:
            continue
        if ch in CONTROL_CHANNELS:
            cols = _columns(type(msg))
            t = out.get(ch) or out.setdefault(ch, Table(LOG_COLUMNS + tuple(c[0] for c in cols), type(msg)))
            t.rows.append((ev.number, ev.utime) + tuple(c[4](msg) for c in cols))
            continue
        items = _batch_items(type(msg))
        per_channel = chunks.setdefault(ch, {})
        if items:
            h = msg.header
            _one_run(path, runs, h.run_id, ev.number)
            key = (h.realization, h.attempt, h.window)
            old = per_channel.get(key)
            if old is not None:
                if old.data != ev.data:
                    raise LogError("%s: %s, realization %d, attempt %d, window %d: the batch of event %d differs from "
                                   "the one of event %d (a duplicate that is no resent copy)"
                                   % ((path, ch) + key + (ev.number, old.event)))
                copies[ch] = copies.get(ch, 0) + 1
                continue
            chunk = per_channel[key] = _Chunk(ev.number, key, (h.utime_begin, h.utime_end), h.seq, ev.data)
            samples = getattr(msg, items)
        else:
            g = current
            key = (g.realization, g.attempt, g.window) if g else (-1, -1, -1)
            chunk = per_channel.get(key)
            if chunk is None:
                chunk = per_channel[key] = _Chunk(ev.number, key, (g.utime_begin, g.utime_end) if g else (-1, -1))
            if g is not None:  # a copy is known as one only within a grant
                if ev.data in chunk.seen:
                    copies[ch] = copies.get(ch, 0) + 1
                    continue
                chunk.seen.add(ev.data)
            samples = [msg]
        if samples and ch not in out:
            cls = type(samples[0])
            out[ch] = Table(LOG_COLUMNS + WINDOW_COLUMNS + tuple(c[0] for c in _columns(cls)), cls)
        base = (ev.number, ev.utime) + key + chunk.span
        for s in samples:
            chunk.rows.append(base + tuple(c[4](s) for c in _columns(type(s))))

    if not n_events:
        raise LogError("%s: an empty file, no LCM event in it" % path)
    last = {}  # realization -> its last attempt
    for r, a in list(grants) + [k[:2] for per in chunks.values() for k in per]:
        last[r] = max(last.get(r, a), a)
    later, end = {}, finish  # realization -> the last START of a later realization, or FINISH
    for r in sorted(starts, reverse=True):
        later[r] = end
        end = max(end, starts[r])
    _check_grants(path, grants, last, later, abort)
    dropped = {}
    for ch, per in chunks.items():
        _check_windows(path, ch, per, grants, last, acks)
        t = out.setdefault(ch, Table(LOG_COLUMNS + WINDOW_COLUMNS, None))  # only empty batches
        for key, chunk in per.items():
            if all_attempts or key[0] < 0 or key[1] == last[key[0]]:
                t.rows.extend(chunk.rows)
            else:
                dropped[ch] = dropped.get(ch, 0) + len(chunk.rows)
    return out, copies, dropped


def _check_grants(path, grants, last, later, abort):
    """Each realization's last attempt was granted windows 0..L once, L the last, and the clock
    moved on after it (a later realization or FINISH)."""
    why = " (the run aborted: %s)" % abort if abort else ""
    for (r, a), g in sorted(grants.items()):
        if a != last[r]:
            continue
        where = "%s: SIM_WINDOW, realization %d, attempt %d (its last)" % (path, r, a)
        ws = sorted(g)
        if ws != list(range(len(ws))):
            raise LogError("%s: the grant of window %d is missing (the log lost it)"
                           % (where, min(set(range(len(ws) + 1)) - set(ws))))
        if not g[ws[-1]][1].last_window or any(g[w][1].last_window for w in ws[:-1]):
            raise LogError("%s did not complete: its grants end at window %d, not at the realization's last "
                           "window; the run failed or the log was cut%s" % (where, ws[-1], why))
        if later.get(r, -1) < g[ws[-1]][0]:
            raise LogError("%s did not complete: the clock never moved past its last window (no later "
                           "realization or FINISH); the run failed or the log was cut%s" % (where, why))


def _check_windows(path, ch, per, grants, last, acks):
    """A channel's last attempts: batches of every window once, in order, seq +1 each, with
    their grant's span; as many samples per window as the publisher's OK ack lists."""
    mine = {}
    for key, chunk in per.items():
        if key[0] >= 0 and key[1] == last[key[0]]:
            mine.setdefault(key[:2], []).append(chunk)
    batches = any(c.seq is not None for cs in mine.values() for c in cs)
    if batches:  # a batch per granted window, even an empty one
        mine.update({k: [] for k in grants if k[1] == last[k[0]] and k not in mine})
    mine.update({k[:2]: [] for k in acks if k[2] == ch and k[1] == last.get(k[0]) and k[:2] not in mine})
    for (r, a), cs in sorted(mine.items()):
        where = "%s: %s, realization %d, attempt %d" % (path, ch, r, a)
        g = grants.get((r, a), {})
        if batches:
            for i, c in enumerate(cs):
                if c.key[2] != i:
                    raise LogError("%s: window %d is missing (the next batch, event %d, is window %d)"
                                   % (where, i, c.event, c.key[2]))
                if c.seq != cs[0].seq + i:
                    raise LogError("%s: window %d (event %d) has seq %d, expected %d (the publisher lost or "
                                   "repeated a message)" % (where, i, c.event, c.seq, cs[0].seq + i))
                if i in g and c.span != (g[i][1].utime_begin, g[i][1].utime_end):
                    raise LogError("%s: window %d (event %d) spans [%d, %d) us, its grant [%d, %d) us"
                                   % ((where, i, c.event) + c.span + (g[i][1].utime_begin, g[i][1].utime_end)))
            if g and len(cs) != len(g):
                raise LogError("%s: window %d is missing (%s; the attempt has %d windows)"
                               % (where, len(cs), "the log has no batch of it" if not cs else
                                  "the stream ends after window %d" % (len(cs) - 1), len(g)))
        listed = acks.get((r, a, ch), {})
        have = {c.key[2]: len(c.rows) for c in cs}
        for w in sorted(set(have) | set(listed)):
            if w in listed and listed[w] != have.get(w, 0):
                raise LogError("%s, window %d: %d sample(s) in the log, the publisher's OK ack lists %d (the log "
                               "lost a message)" % (where, w, have.get(w, 0), listed[w]))


def tables(path, channels=None, all_attempts=False):
    """{channel: {column: numpy array}}: read() as numpy columns (numbers, booleans, strings)."""
    t, _, _ = read(path, channels, all_attempts)
    return {ch: x.arrays() for ch, x in t.items()}


def units(lcm_dir=None, meanings=None):
    """{type name: {field: unit text}} from the comments of lcmtypes/*.lcm ('[m] slant range');
    with a dict `meanings`, it is filled as {type name: {field: the comment's text}}."""
    lcm_dir = lcm_dir or os.path.join(_ROOT, "lcmtypes")
    out = {}
    field = re.compile(r"^\s*\w+\s+(\w+)\s*(?:\[[^\]]*\]\s*)*;\s*//.*?\[([^\]]*)\]")
    comment = re.compile(r"^\s*\w+\s+(\w+)\s*(?:\[[^\]]*\]\s*)*;\s*//\s*(?:\[[^\]]*\])?\s*(.*\S)")
    for name in sorted(os.listdir(lcm_dir)) if os.path.isdir(lcm_dir) else []:
        if not name.endswith(".lcm"):
            continue
        cur = None
        with open(os.path.join(lcm_dir, name), encoding="utf-8") as f:
            for line in f:
                m = re.match(r"^\s*struct\s+(\w+)", line)
                if m:
                    cur = out.setdefault(m.group(1), {})
                    if meanings is not None:
                        curm = meanings.setdefault(m.group(1), {})
                m = comment.match(line)
                if m and cur is not None and meanings is not None:
                    curm[m.group(1)] = m.group(2).strip()
                m = field.match(line)
                if m and cur is not None:
                    cur[m.group(1)] = m.group(2).strip()
    return out


def column_units(table, unit_map=None):
    """{column: unit text} where the .lcm comments give one: a scalar's unit; an array element's
    from a list of as many units as the array has elements, or the array's single unit."""
    unit_map = unit_map if unit_map is not None else units()
    sim = "us since Unix epoch, sim time"
    out = {c: u for c, u in (("log_utime", "us since Unix epoch"), ("window_utime_begin", sim),
                             ("window_utime_end", sim)) if c in table.columns}
    if table.type is None:
        return out
    counts = {}
    for name, owner, f, index, _ in _columns(table.type):
        if index is not None:
            counts[(owner, f)] = counts.get((owner, f), 0) + 1
    for name, owner, f, index, _ in _columns(table.type):
        u = unit_map.get(owner, {}).get(f)
        if u is None:
            continue
        if index is None:
            out[name] = u
            continue
        parts = [p.strip() for p in u.split(",")]
        if len(parts) == 1:
            out[name] = u
        elif len(index) == 1 and len(parts) == counts[(owner, f)]:
            out[name] = parts[index[0]]
    return out


_FIXED_MEANINGS = {
    "log_event": "event number in the log file",
    "log_utime": "when the recorder received the message",
    "realization": "Monte Carlo realization (flight) number",
    "attempt": "attempt of the realization (a realization that lost a message is run again)",
    "window": "lock-step window number within the realization",
    "window_utime_begin": "start of the window the sample belongs to",
    "window_utime_end": "end of the window the sample belongs to",
}


def column_meanings(table, meaning_map=None):
    """{column: meaning}: the .lcm comment of the column's field (an array element's with its
    index), the log and window columns' own, else 'FIELD of TYPE'."""
    if meaning_map is None:
        meaning_map = {}
        units(meanings=meaning_map)
    out = {c: m for c, m in _FIXED_MEANINGS.items() if c in table.columns}
    if table.type is None:
        return out
    for name, owner, f, index, _ in _columns(table.type):
        text = meaning_map.get(owner, {}).get(f) or "%s of %s" % (f, owner)
        out[name] = text if index is None else "%s (element %s)" % (text, ", ".join(str(i) for i in index))
    return out


def write_csv(table, path, unit_map=None, meaning_map=None):
    """One table as CSV: a header of plain column names (letters, digits and '_': numpy's
    genfromtxt(names=True) and pandas read them as they are), then the rows (numbers in Python's
    shortest round-trip form, booleans 1/0, text percent-encoded); beside it PATH without '.csv'
    + '.units.json' (csvio.py): every column's unit where the .lcm comments give one (else "")
    and meaning."""
    from . import csvio
    u = column_units(table, unit_map)
    m = column_meanings(table, meaning_map)
    # text columns (strings, variable-length arrays joined by ';') are percent-encoded
    text = [any(isinstance(r[j], str) for r in table.rows) for j in range(len(table.columns))]
    csvio.write_csv(path, [(c, u.get(c, ""), m.get(c) or c, "percent" if t else None)
                           for c, t in zip(table.columns, text)], table.rows)

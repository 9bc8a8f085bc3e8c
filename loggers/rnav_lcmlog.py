"""The project's LCM event logs in Python: Debian's python3 (numpy for arrays), no LCM C extension.

    import sys; sys.path.insert(0, "loggers")
    import rnav_lcmlog
    t = rnav_lcmlog.tables("/tmp/run.lcmlog")          # {channel: {column: numpy array}}
    plots = t["PRL_APOI"]                                # one row per radar plot
    plots["range_m"], plots["utime"], plots["realization"]

Messages are decoded with the types lcm-gen --python writes into build/python/rnav (part of
every build; set RNAV_PYTHON_TYPES to another folder holding the rnav package). Each project
channel becomes a table with one row per sample: a batch message (runner.wire=batch) gives a
row per element, with its header's realization, attempt and window; a sample message
(runner.wire=sample) one row. Fixed-size arrays become one column per element (p_TA_L_0,
p_TA_L_1, p_TA_L_2); variable-length arrays of strings are joined with ';'. Every row carries
`log_event` (the event number) and `log_utime` (when the recorder received it [us since the
Unix epoch]; `utime` is the sample's time of validity). A byte-identical copy of an earlier
message on the same channel (a lock-step resend) is skipped and counted in `copies`. Units: the
field names and lcmtypes/*.lcm.

Nothing is read silently wrong: the file is checked event by event (sync word, sizes within the
file) and every message must decode as the type its fingerprint names, using all its bytes;
otherwise LogError names the file, the byte offset or event, and the channel.
"""

import csv
import importlib
import os
import pkgutil
import struct
import sys

SYNC = 0xEDA1DA01
_HEADER = struct.Struct(">IqqII")  # sync, event number, receive utime, channel length, data length
MAX_CHANNEL_BYTES = 256            # LCM channel names are short; a longer one is a corrupt header


class LogError(Exception):
    """A log that is not what it claims: the message names the file and where."""


def _types_dir():
    d = os.environ.get("RNAV_PYTHON_TYPES")
    if d:
        return d
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    return os.path.join(os.environ.get("RNAV_BUILD", os.path.join(root, "build")), "python")


def message_types():
    """{8-byte packed fingerprint: class} of every project type (build/python/rnav)."""
    d = _types_dir()
    if not os.path.isfile(os.path.join(d, "rnav", "__init__.py")):
        raise LogError("no generated Python types in %s (build the project: scripts/setup)" % d)
    if d not in sys.path:
        sys.path.insert(0, d)
    import rnav  # noqa: F401  (the generated package)
    out = {}
    for m in pkgutil.iter_modules([os.path.join(d, "rnav")]):
        cls = getattr(importlib.import_module("rnav." + m.name), m.name)
        out[cls._get_packed_fingerprint()] = cls
    return out


def events(path):
    """(event number, receive utime [us], channel, data bytes) of each event, checked."""
    with open(path, "rb") as f:
        blob = f.read()
    off = 0
    while off < len(blob):
        if len(blob) - off < _HEADER.size:
            raise LogError("%s: byte %d: a truncated event header (%d bytes left of %d)"
                           % (path, off, len(blob) - off, _HEADER.size))
        sync, num, utime, clen, dlen = _HEADER.unpack_from(blob, off)
        if sync != SYNC:
            raise LogError("%s: byte %d: no LCM sync word 0x%08X (found 0x%08X): not an LCM event log, "
                           "or corrupt" % (path, off, SYNC, sync))
        start = off + _HEADER.size
        if not 0 < clen <= MAX_CHANNEL_BYTES:
            raise LogError("%s: byte %d, event %d: channel length %d is out of range (1..%d)"
                           % (path, off, num, clen, MAX_CHANNEL_BYTES))
        if dlen > len(blob) - start - clen:
            raise LogError("%s: byte %d, event %d: data length %d runs past the end of the file (%d bytes left)"
                           % (path, off, num, dlen, len(blob) - start - clen))
        try:
            channel = blob[start:start + clen].decode("ascii")
        except UnicodeDecodeError:
            raise LogError("%s: byte %d, event %d: the channel name is not ASCII" % (path, off, num))
        yield num, utime, channel, blob[start + clen:start + clen + dlen]
        off = start + clen + dlen


def _flatten(msg, prefix=""):
    """Scalar columns of one message or element: {name: value}."""
    out = {}
    for field in msg.__slots__:
        v = getattr(msg, field)
        name = prefix + field
        if isinstance(v, (list, tuple)):
            if v and all(isinstance(x, str) for x in v):
                out[name] = ";".join(v)
            elif all(isinstance(x, (int, float, bool)) for x in v):
                for i, x in enumerate(v):
                    out["%s_%d" % (name, i)] = x
            else:
                raise LogError("field %s holds an array of structures the tables do not flatten" % name)
        elif hasattr(v, "__slots__"):
            out.update(_flatten(v, name + "_"))
        else:
            out[name] = v
    return out


def _batch_array(msg):
    """The element array of a batch type (a `header` and an `n`-sized array), else None."""
    slots = msg.__slots__
    if "header" in slots and "n" in slots and len(slots) == 3:
        return [s for s in slots if s not in ("header", "n")][0]
    return None


def rows(path, channels=None, types=None, copies=None):
    """{channel: [row dict, ...]} of every decodable channel (or only `channels`)."""
    types = types if types is not None else message_types()
    seen, out = {}, {}
    for num, utime, channel, data in events(path):
        if channels is not None and channel not in channels:
            continue
        cls = types.get(bytes(data[:8]))
        if cls is None:
            if channel == "LCM_SELF_TEST":
                continue
            raise LogError("%s: event %d on channel %s: fingerprint %s is no project type (a foreign "
                           "message, or corrupt)" % (path, num, channel, bytes(data[:8]).hex()))
        if data in seen.setdefault(channel, set()):
            if copies is not None:
                copies[channel] = copies.get(channel, 0) + 1
            continue
        seen[channel].add(data)
        try:
            msg = cls.decode(data)
            if msg.encode() != data:
                raise ValueError("bytes left over")
        except Exception as e:  # the generated decoder raises struct.error, ValueError, ...
            raise LogError("%s: event %d on channel %s does not decode as rnav.%s (%s)"
                           % (path, num, channel, cls.__name__, e))
        base = {"log_event": num, "log_utime": utime}
        arr = _batch_array(msg)
        table = out.setdefault(channel, [])
        if arr is None:
            row = dict(base)
            row.update(_flatten(msg))
            table.append(row)
        else:
            h = msg.header
            for el in getattr(msg, arr):
                row = dict(base, realization=h.realization, attempt=h.attempt, window=h.window)
                row.update(_flatten(el))
                table.append(row)
    return out


def tables(path, channels=None, copies=None):
    """{channel: {column: numpy array}}: rows() as columns (numbers as numpy arrays)."""
    import numpy as np
    out = {}
    for channel, rs in rows(path, channels, copies=copies).items():
        cols = list(rs[0].keys()) if rs else []
        out[channel] = {c: np.array([r.get(c) for r in rs]) for c in cols}
    return out


def write_csv(rs, path):
    """One channel's rows as CSV (header: the column names; numbers at full precision)."""
    cols = []
    for r in rs:
        for c in r:
            if c not in cols:
                cols.append(c)
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(cols)
        for r in rs:
            w.writerow([repr(r[c]) if isinstance(r.get(c), float) else r.get(c, "") for c in cols])

#!/usr/bin/env python3
"""The multi-sensor diagnosis on a busy harbour from the independent generator
(scripts/flightgen.py shipradar scene=harbour: 40 ships 250 m - 9 km away, moored side by side,
hulls 10-300 m whose echo is their near side while AIS gives the antenna, sea clutter and land,
coloured noise, AIS every 2-10 s on whole seconds; its radar stamps each detection at its own
illumination time), fixed seeds, 15 minutes each, diagnosed as a radar engineer would (4 deg /
200 m gates, AIS gap 12 s, nominal 1 deg and 40 m):

1. the radar is read as rotations of its period (2.5 s within 1 %), its gates recentred across
   targets with a 1 deg bearing bias, and the hour is not refused;
2. a 1 deg radar bearing bias is named within +-0.15 deg (the bound the diagnosis is asked to
   meet on a harbour hour), asked across the targets (replicated over at least 5 of them);
3. with no radar error no radar-wide mean effect is named (bearing or range bias, range gain,
   clock, scan stamp): the ships' near-side echoes are per ship (echo_range_offset), not a radar
   range bias (on an hour of this harbour, before a range bias had to be one value across the
   targets, a radar range bias of -21 m was named);
4. no antenna_offset named beyond its ship's true hull, no clock (the radar's or a reference's)
   beyond 0.3 s (with a 2 SE margin on the physical bounds and reference clocks up to 10 s, the
   nominal recording named a 55 m starboard offset on a 35 m beam (within 2 SE of it) and a 7.3 s reference
   clock, and the biased one a 12 s reference clock).

  python3 test/check_harbour.py SOURCE_DIR BUILD_DIR
"""
import json
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(sys.argv[1], "scripts"))
import flightgen  # noqa: E402
from generated_checks import Checks, run  # noqa: E402

SRC, BUILD = sys.argv[1], sys.argv[2]
DIAG = os.path.join(BUILD, "bin", "rnav_diagnose")
OPTS = ["--reference-max-gap", "12", "--gate-deg", "4", "--gate-m", "200", "--sigma-deg", "1", "--sigma-range-m", "40",
        "--threads", "2"]
RADAR_WIDE = {"bearing_bias", "range_bias", "range_gain", "time_offset", "scan_time_offset"}
checks = Checks("check_harbour")
check = checks.check


def hour(tmp, name, seed, bias_deg):
    """Generate and diagnose; (report or None, the generator's ships by id)."""
    folder = os.path.join(tmp, name)
    r = flightgen.shipradar(folder, seed, {"scene": "harbour", "duration_s": "900", "bearing_bias_deg": str(bias_deg)})
    out = folder + ".json"
    p = run(DIAG, "multi", folder, "--json", out, *OPTS)
    check(p.returncode == 0, "%s: diagnosed, not refused: %s" % (name, p.stderr.strip()[-200:]))
    return (json.load(open(out)) if p.returncode == 0 else None), {str(s["id"]): s for s in r["targets"]}


def named(rep):
    """The mean effects named, each estimate as a list (a one-parameter effect's is a number in the JSON)."""
    out = [e for e in rep["effects"] if e["name"] not in ("target_maneuver", "noise_scale", "correlated_noise", "outliers")]
    for e in out:
        e["estimate"] = e["estimate"] if isinstance(e["estimate"], list) else [e["estimate"]]
    return out


def physical(rep, ships, name):
    for e in named(rep):
        sc = e["scope"]
        if e["name"] in ("time_offset", "truth_time_offset"):
            check(abs(e["estimate"][0]) <= 0.3, "%s: %s [%s] %.3g s within 0.3 s" % (name, e["name"], sc, e["estimate"][0]))
        if e["name"] == "antenna_offset" and sc.get("target") in ships:
            s = ships[sc["target"]]
            ok = abs(e["estimate"][0]) <= s["length_m"] and abs(e["estimate"][1]) <= s["beam_m"]
            check(ok, "%s: antenna_offset of %s (%.1f, %.1f) m on its hull %.0f x %.0f m" %
                  (name, sc["target"], e["estimate"][0], e["estimate"][1], s["length_m"], s["beam_m"]))


with tempfile.TemporaryDirectory(prefix="check_harbour.") as tmp:
    rep, ships = hour(tmp, "bias1", 5, 1.0)
    if rep:
        a = rep["association"]["radar"]
        check(abs(a["rotation_period_s"] - 2.5) < 0.025, "bias1: read as rotations of %.4g s (2.5 s)" % a["rotation_period_s"])
        check(a["shift_rule"] == "targets" and abs(a["gate_shift_bearing_rad"] * 180 / math.pi - 1) < 0.3,
              "bias1: gates recentred across %d targets by %.3g deg" % (a["shift_targets"], a["gate_shift_bearing_rad"] * 180 / math.pi))
        bb = [e for e in named(rep) if e["name"] == "bearing_bias" and e["scope"].get("sensor") == "radar" and not e["scope"].get("target")]
        est = bb[0]["estimate"][0] * 180 / math.pi if bb else float("nan")
        check(bool(bb) and abs(est - 1.0) <= 0.15, "bias1: radar bearing bias named %.3f deg (1 +- 0.15)" % est)
        reps = bb[0].get("replication", {}).get("recordings", []) if bb else []
        check(len(reps) >= 5, "bias1: the bias asked across %d targets" % len(reps))
        physical(rep, ships, "bias1")
    rep, ships = hour(tmp, "nominal", 6, 0.0)
    if rep:
        wide = ["%s [%s]" % (e["name"], e["scope"]) for e in named(rep)
                if e["name"] in RADAR_WIDE and not e["scope"].get("target")]
        check(not wide, "nominal: no radar-wide effect named (%s)" % (", ".join(wide) or "none"))
        echo = [e for e in named(rep) if e["name"] == "echo_range_offset"]
        print("nominal: %d per-ship echo range offsets named" % len(echo))
        physical(rep, ships, "nominal")
sys.exit(checks.finish())

"""Legend text for the effects a diagnosis named (rnav_diagnose's JSON report), so a residual
plot says what its extended model holds: 'time_offset [sensor radar]: s = 1.15 +- 0.06'.
Angles are shown in degrees (a parameter 'rad' or '*_rad' as 'deg' or '*_deg', '*_radps' as
'*_degps'); noise findings (noise_scale, correlated_noise, outliers) and target manoeuvres are
not mean effects and are left out.
"""
import math

NOT_MEAN = {"noise_scale", "correlated_noise", "outliers", "target_maneuver"}
BARE_UNITS = {"1", "s", "m", "deg", "degps", "m/s", "ratio"}


def _shown(param, value):
    """(parameter name, value) with an angle in degrees."""
    if value is None:
        return param, None
    if param == "rad":
        return "deg", math.degrees(value)
    if param.endswith("_rad"):
        return param[:-4] + "_deg", math.degrees(value)
    if param.endswith("_radps"):
        return param[:-6] + "_degps", math.degrees(value)
    return param, value


def _list(x, n):
    return list(x) if isinstance(x, list) else [x] * n if n == 1 else [x] + [None] * (n - 1)


def scope_text(e):
    s = e.get("scope") or {}
    parts = [p for p in (s.get("sensor"), s.get("target")) if p]
    where = ":".join(parts) if len(parts) == 2 else ("sensor " + parts[0] if s.get("sensor") else
                                                    "target " + parts[0] if parts else "")
    if e.get("channel") and not where:
        where = e["channel"]
    if s.get("recording"):
        where = (where + " in " if where else "recording ") + s["recording"]
    return where


def label(e):
    """'name [scope]: p = v +- se, ...' of one effect of the report."""
    params = e.get("params") or []
    est, se = _list(e.get("estimate"), len(params)), _list(e.get("stderr"), len(params))
    vals = []
    for p, v, s in zip(params, est, se):
        name, v = _shown(p, v)
        _, s = _shown(p, s)
        if v is None:
            continue
        value = "%.3g%s" % (v, "" if s is None else " +- %.2g" % s)
        # a parameter named by its unit alone (the multi-sensor report: "s", "deg", "1")
        vals.append(value + ("" if name == "1" else " " + name) if name in BARE_UNITS else "%s = %s" % (name, value))
    where = scope_text(e)
    return "%s%s%s" % (e["name"], " [%s]" % where if where else "", ": " + ", ".join(vals) if vals else "")


def mean_effects(report):
    """The report's named mean effects (not the nominal parameters, not noise findings)."""
    return [e for e in report.get("effects", []) if not e.get("nominal") and e.get("name") not in NOT_MEAN]


# Multi-sensor entries that move one measured quantity only (estimators/diagnosis/multi_problem.cpp;
# bias_step is a jump in the bearings); the others (clocks, lever arms, scan stamps) move both.
ONE_QUANTITY = {"range_gain": "range", "range_bias": "range", "bearing_bias": "bearing", "bias_step": "bearing"}


def applies(e, sensor=None, target=None, recording=None, quantity=None):
    """Whether effect e acts on a sensor:target (of a recording) and, if given, on the measured
    quantity ("range" or "bearing"): its scope is empty there or names them."""
    s = e.get("scope") or {}
    if quantity is not None and ONE_QUANTITY.get(e.get("name"), quantity) != quantity:
        return False
    return ((not s.get("sensor") or sensor is None or s["sensor"] == sensor) and
            (not s.get("target") or target is None or s["target"] == target) and
            (not s.get("recording") or recording is None or s["recording"] == recording))


def legend(report, sensor=None, target=None, recording=None, limit=6, quantity=None):
    """'extended model' and, one per line, the effects that act here (at most `limit`)."""
    named = mean_effects(report) if report else []
    es = [label(e) for e in named if applies(e, sensor, target, recording, quantity)]
    if not es:
        return "extended model" + ("" if not report else " (no mean effect named)" if not named else
                                   " (no effect named acts here)")
    more = len(es) - limit
    return "extended model:\n" + "\n".join(es[:limit]) + ("\n(and %d more)" % more if more > 0 else "")

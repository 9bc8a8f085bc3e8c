#!/usr/bin/env python3
"""ctest python.effect_labels: the residual plots' legends name each effect the diagnosis named,
with its estimate (scripts/rnav/effect_labels.py), on a hand-made report: an angle shown in degrees,
a parameter named by its unit shown after the value, the scope and recording written out, an
effect only on the panels it acts on, noise findings and nominal parameters left out.
Usage: PYTHONPATH=SOURCE_DIR/scripts check_effect_labels.py (ctest sets it)"""
import math
import sys

from rnav import effect_labels as L

report = {"effects": [
    {"name": "range_bias", "nominal": True, "params": ["m"], "estimate": 6.1, "stderr": 1.2},
    {"name": "bias_step", "scope": {}, "params": ["t_s", "glide_rad"], "estimate": [237.0, math.radians(0.264)],
     "stderr": [3.4, math.radians(0.03)]},
    {"name": "bearing_bias", "scope": {"sensor": "ir", "target": None, "recording": "sc4"}, "params": ["rad"],
     "estimate": math.radians(-4.61), "stderr": math.radians(0.26)},
    {"name": "antenna_offset", "scope": {"sensor": "radar", "target": "gunnerus"}, "params": ["along_m", "starboard_m"],
     "estimate": [-7.1, -0.29], "stderr": [0.15, 0.12]},
    {"name": "correlated_noise", "scope": {"sensor": "eo", "target": "havfruen"}, "params": ["tau_s", "correlated_share"],
     "estimate": [2.5, 0.999], "stderr": [0.7, None]},
]}
fails = []


def expect(got, want, what):
    if got != want:
        fails.append("%s: %r, expected %r" % (what, got, want))


expect([e["name"] for e in L.mean_effects(report)], ["bias_step", "bearing_bias", "antenna_offset"],
       "mean effects (no nominal parameter, no noise finding)")
expect(L.label(report["effects"][1]), "bias_step: t_s = 237 +- 3.4, glide_deg = 0.264 +- 0.03", "a step in degrees")
expect(L.label(report["effects"][2]), "bearing_bias [sensor ir in sc4]: -4.61 +- 0.26 deg", "a bias named by its unit")
expect(L.label(report["effects"][3]), "antenna_offset [radar:gunnerus]: along_m = -7.1 +- 0.15, starboard_m = -0.29 +- 0.12",
       "a two-parameter offset")
expect(L.legend(report, "ir", "gunnerus", "sc4").split("\n"),
       ["extended model:", "bias_step: t_s = 237 +- 3.4, glide_deg = 0.264 +- 0.03",
        "bearing_bias [sensor ir in sc4]: -4.61 +- 0.26 deg"], "the ir:gunnerus panel of sc4")
expect("bearing_bias" in L.legend(report, "ir", "gunnerus", "sc5"), False, "another recording's bias")
expect("antenna_offset" in L.legend(report, "radar", "havfruen"), False, "another boat's antenna")
expect(L.legend({"effects": report["effects"][4:]}, "eo", "havfruen"), "extended model (no mean effect named)",
       "only a noise finding")
expect(L.legend({"effects": report["effects"][2:3]}, "eo", "havfruen"), "extended model (no effect named acts here)",
       "effects elsewhere")
expect(L.legend(None), "extended model", "no report")
# a range gain moves no bearing: the bearing panel of its sensor does not list it, its range panel does
gain = {"effects": [{"name": "range_gain", "scope": {"sensor": "lidar", "target": None}, "params": ["1"],
                     "estimate": -0.0163, "stderr": 0.00099}]}
expect(L.legend(gain, "lidar", "gunnerus", quantity="bearing"), "extended model (no effect named acts here)",
       "a range gain on a bearing panel")
expect("range_gain" in L.legend(gain, "lidar", "gunnerus", quantity="range"), True, "a range gain on a range panel")
expect("antenna_offset" in L.legend(report, "radar", "gunnerus", quantity="bearing"), True,
       "a lever arm moves bearings too")
for f in fails:
    print("FAIL: " + f)
print("%d failure(s)" % len(fails))
sys.exit(1 if fails else 0)

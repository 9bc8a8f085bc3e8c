#!/usr/bin/env bash
# ctest sweep.grid_and_resume: scripts/sweep runs one ensemble per grid setting, its rows equal
# the settings' own runs, a rerun reuses finished settings and rebuilds the same table, an
# unfinished setting is run again, settings on 2 MPI ranks or 2 at once give the same table, and bad grids are refused naming the option;
# sweep.units.json describes every column of sweep.csv, progress lines count the settings with an ETA, and sweep.png plots
# exactly the figures whose settings differ by more than 2 standard errors (sweep.json's plotted).
# Usage: check_sweep.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
SRC=$1
export RNAV_BUILD=$2
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
SW=("$SRC/scripts/sweep" paper --grid radar.x_m=-1500,-1000 --grid prl.period_s=0.5,1 --realizations 6 --seed 3 --out "$T/sw")

"${SW[@]}" 2>"$T/first.err" || { cat "$T/first.err"; fail "the sweep failed"; }
grep -q "4 settings: 4 run, 0 from an earlier run, 0 failed" "$T/first.err" || { cat "$T/first.err"; fail "not 4 settings run"; }
grep -q "sweep: setting 3 of 4 (002): radar.x_m=-1000 prl.period_s=0.5" "$T/first.err" || { cat "$T/first.err"; fail "progress does not name the setting's place and values"; }
grep -qx "sweep: 0 of 4 done; ETA unknown" "$T/first.err" || { cat "$T/first.err"; fail "no first progress line"; }
for k in 1 2 3; do
  grep -qE "^sweep: $k of 4 done \(0 failed\) — last 00[0-3] \(radar\.x_m=-1[05]00 prl\.period_s=(0\.5|1)\) ok in [0-9.]+ s; ETA [1-9][0-9]* (s|min)" \
    "$T/first.err" || { cat "$T/first.err"; fail "no progress line '$k of 4 done' with the setting's values and an ETA above 0"; }
done
grep -qE "^sweep: 4 of 4 done \(0 failed\) — last .* ok in [0-9.]+ s; ETA 0 s$" "$T/first.err" || { cat "$T/first.err"; fail "no last progress line"; }
[[ $(wc -l <"$T/sw/sweep.csv") == 5 ]] || fail "sweep.csv does not hold a header and 4 rows"
[[ -s $T/sw/sweep.png && -s $T/sw/sweep.json ]] || fail "sweep.png or sweep.json missing"

# sweep.units.json beside sweep.csv: every column of the header, in its order, with a unit (a grid
# key's from its suffix) and a meaning; sweep.json's plotted and unchanged split the APOI and TOI
# figures by the 2-SE rule, recomputed here from sweep.csv.
check_plot() {
  /usr/bin/python3 - "$1" <<'PY'
import csv, itertools, json, math, re, sys
d = sys.argv[1]
header = next(csv.reader(open(d + "/sweep.csv")))
units = json.load(open(d + "/sweep.units.json"))
assert list(units) == header, ("units.json's columns are not the header's", list(units), header)
assert all(v["meaning"] and isinstance(v["unit"], str) for v in units.values()), units
sw = json.load(open(d + "/sweep.json"))
for k, _ in sw["grid"]:
    col = k.replace(".", "_")
    assert col in header, (k, header)
    assert units[col]["unit"] == {"m": "m", "s": "s"}[k.rsplit("_", 1)[1]], (col, units[col])
rows = list(csv.DictReader(open(d + "/sweep.csv")))
figs = [c for c in header if re.fullmatch(r"(apoi|toi)_[0-9]+_[xzy]_m", c)]
assert len(figs) == 12 and all(units[c]["unit"] == "m" and units[c + "_se"]["unit"] == "m" for c in figs), figs

def changes(c):
    v = [(float(r[c]), float(r[c + "_se"])) for r in rows]
    return any(abs(a - b) > 2 * math.hypot(sa, sb) for (a, sa), (b, sb) in itertools.combinations(v, 2))
want = [c for c in figs if changes(c)]
assert sw["plotted"] == want, ("plotted", sw["plotted"], "change by > 2 SE", want)
assert sw["unchanged"] == [c for c in figs if c not in want], sw["unchanged"]
print(" ".join(want) or "none")
PY
}
plotted=$(check_plot "$T/sw") || fail "sweep.units.json or the plotted columns are wrong"
# A range bias of 6 and 60 m moves the APOI error along the runway (X), not the lateral (Z) one.
"$SRC/scripts/sweep" paper --grid prl.bias_range_m=6,60 --grid radar.x_m=-1500,-1000 --realizations 6 --seed 3 --jobs 2 \
  --out "$T/bias" 2>"$T/bias.err" || { cat "$T/bias.err"; fail "the bias sweep failed"; }
plotted=$(check_plot "$T/bias") || fail "the bias sweep's units.json or plotted columns are wrong"
[[ " $plotted " == *" apoi_4000_x_m "* && " $plotted " != *" apoi_4000_z_m "* ]] || fail "bias sweep plotted: $plotted"

# Row 3 (radar.x_m=-1000, prl.period_s=0.5: the first key varies slowest) equals that setting's own run.
"$SRC/scripts/run" paper --inproc --no-plots --realizations 6 --seed 3 --set radar.x_m=-1000 --set prl.period_s=0.5 \
  --out "$T/one" >/dev/null 2>&1 || fail "the single run failed"
/usr/bin/python3 - "$T/sw/sweep.csv" "$T/one/table2_detail.json" <<'PY' || fail "row 3 differs from the setting's own run"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
r = rows[2]
assert (r["radar_x_m"], r["prl_period_s"]) == ("-1000", "0.5"), r
d = json.load(open(sys.argv[2]))
for kind in ("APOI", "TOI"):
    for rng, v in d[kind].items():
        for axis, m, se in zip("xzy", v["mean"], v["stderr"]):
            col = "%s_%s_%s_m" % (kind.lower(), rng, axis)
            assert abs(float(r[col]) - m) <= 1e-9 * max(1, abs(m)), (col, r[col], m)
            assert abs(float(r[col + "_se"]) - se) <= 1e-9 * max(1, abs(se)), (col, r[col + "_se"], se)
PY

# Resume: nothing to run, the same table; a setting left unfinished is run again, the same table.
cp "$T/sw/sweep.csv" "$T/first.csv"
"${SW[@]}" 2>"$T/second.err" || fail "the rerun failed"
grep -q "4 settings: 0 run, 4 from an earlier run" "$T/second.err" || { cat "$T/second.err"; fail "the rerun ran settings again"; }
cmp -s "$T/first.csv" "$T/sw/sweep.csv" || fail "the rerun's sweep.csv differs"
rm "$T/sw/settings/002/job.json"
"${SW[@]}" 2>"$T/third.err" || fail "the resumed sweep failed"
grep -q "4 settings: 1 run, 3 from an earlier run" "$T/third.err" || { cat "$T/third.err"; fail "the unfinished setting was not run again"; }
grep -qx "sweep: 0 of 1 done, 3 kept from an earlier run; ETA unknown" "$T/third.err" || { cat "$T/third.err"; fail "kept settings counted in the progress"; }
grep -qE "^sweep: 1 of 1 done \(0 failed\) — last 002 \(radar.x_m=-1000 prl.period_s=0.5\) ok in [0-9.]+ s; ETA 0 s$" "$T/third.err" \
  || { cat "$T/third.err"; fail "no progress line for the one setting run again"; }
cmp -s "$T/first.csv" "$T/sw/sweep.csv" || fail "the resumed sweep.csv differs"

# The settings sharded over 2 MPI ranks, and 2 at once on this host: the same table.
if command -v mpirun >/dev/null; then
  "$SRC/scripts/sweep" paper --grid radar.x_m=-1500,-1000 --grid prl.period_s=0.5,1 --realizations 6 --seed 3 --ranks 2 \
    --out "$T/mpi" 2>"$T/mpi.err" || { cat "$T/mpi.err"; fail "the sweep on 2 ranks failed"; }
  cmp -s "$T/first.csv" "$T/mpi/sweep.csv" || fail "sweep.csv on 2 MPI ranks differs"
fi
"$SRC/scripts/sweep" paper --grid radar.x_m=-1500,-1000 --grid prl.period_s=0.5,1 --realizations 6 --seed 3 --jobs 2 \
  --out "$T/jobs" 2>"$T/jobs.err" || { cat "$T/jobs.err"; fail "the sweep with --jobs 2 failed"; }
cmp -s "$T/first.csv" "$T/jobs/sweep.csv" || fail "sweep.csv with --jobs 2 differs"

# Another N into the same folder is refused (its rows would mix two sweeps).
if "$SRC/scripts/sweep" paper --grid radar.x_m=-1500,-1000 --grid prl.period_s=0.5,1 --realizations 7 --seed 3 \
     --out "$T/sw" 2>"$T/other.err"; then fail "another N was accepted into the same folder"; fi
grep -q "holds a sweep of another grid" "$T/other.err" || { cat "$T/other.err"; fail "no clear message for another sweep"; }
# Bad grids.
check_bad() {
  local want=$1; shift
  if "$SRC/scripts/sweep" paper --realizations 3 --out "$T/bad" "$@" 2>"$T/bad.err"; then fail "accepted: $*"; fi
  grep -qF -- "$want" "$T/bad.err" || { cat "$T/bad.err"; fail "no '$want' for: $*"; }
}
check_bad "at least one --grid" 
check_bad "expected key=v1,v2" --grid radar.x_m
check_bad "a value given twice" --grid radar.x_m=1,1
check_bad "key 'radar.x_m' given twice" --grid radar.x_m=1 --grid radar.x_m=2
check_bad "radar.x_mm" --grid radar.x_mm=1,2
check_bad "exclude each other" --grid radar.x_m=1,2 --ranks 2 --setting-ranks 2
check_bad "--jobs must be >= 1" --grid radar.x_m=1,2 --jobs 0
echo "sweep: ok"

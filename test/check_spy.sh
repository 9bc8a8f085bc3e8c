#!/bin/bash
# ctest spy.text_view: scripts/spy without a display shows the terminal view (scripts/spy_text.py).
# Inside a private network namespace (unshare -n: no traffic leaves the machine), a real-time
# paper run at 20x is watched for 6 s: every data channel is decoded by its project type, the
# radar's plots (1 Hz of sim time) arrive at most 20 per second and the aircraft truth (4 Hz) at
# four times their rate (3-5: the two streams start within a window of each other), the last
# plot's range is shown with its unit, and every message the senders numbered is counted on a
# channel. Options: --text and --gui exclude each other; --duration is checked.
# Usage: check_spy.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$(cd "$1" && pwd)
export RNAV_BUILD=$(cd "$2" && pwd)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# (joining a multicast group sends an IGMP report: only inside the private namespace)
out=$(unshare -n bash -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo && DISPLAY= "$0/scripts/spy" --duration 1' "$SRC" 2>&1) ||
  fail "the headless view failed: $out"
grep -q "^spy: 0 channel(s)" <<<"$out" || fail "without DISPLAY the terminal view did not run: $out"
DISPLAY=:99 "$SRC/scripts/spy" --text --gui >/dev/null 2>&1 && fail "--text --gui accepted"
DISPLAY= "$SRC/scripts/spy" --duration -1 >/dev/null 2>&1 && fail "--duration -1 accepted"

unshare -n bash -c '
  ip link set lo up && ip route add 224.0.0.0/4 dev lo || exit 9
  "$0/scripts/run" paper --realtime --speed 20 --realizations 1 --net host --no-plots --out "$1/run" >"$1/run.log" 2>&1 &
  DISPLAY= "$0/scripts/spy" --duration 6 --json "$1/spy.json" >"$1/spy.txt" 2>&1
  wait' "$SRC" "$T"
rc=$?
((rc != 9)) || fail "cannot set up the private network namespace (needs root: unshare -n, ip)"
[[ -s $T/spy.json ]] || { cat "$T/spy.txt" "$T/run.log"; fail "no spy.json"; }
/usr/bin/python3 - "$T/spy.json" <<'PY' || { tail -15 "$T/spy.txt"; exit 1; }
import json, sys
d = json.load(open(sys.argv[1]))
ch = {c["channel"]: c for c in d["channels"]}
bad = []
for name, typ in (("PRL_APOI", "prl_plot_t"), ("PRL_TOI", "prl_plot_t"), ("TRUTH_AIRCRAFT", "aircraft_state_t"),
                  ("NAV_SOLUTION", "nav_solution_t"), ("SIM_WINDOW", "sim_window_t"), ("SIM_ACK", "node_ack_t")):
    if ch.get(name, {}).get("type") != typ:
        bad.append("%s: type %s, not %s" % (name, ch.get(name, {}).get("type"), typ))
apoi, truth = ch.get("PRL_APOI"), ch.get("TRUTH_AIRCRAFT")
if apoi and truth:
    if not (5 <= apoi["mean_rate_hz"] <= 20 * 1.05):
        bad.append("PRL_APOI at %.1f/s (1 Hz x 20 at most)" % apoi["mean_rate_hz"])
    ratio = (truth["messages"] - truth["repeats"]) / max(apoi["messages"] - apoi["repeats"], 1)
    if not 3 <= ratio <= 5:
        bad.append("truth / plots = %.2f, not about 4" % ratio)
    if " range_m=" not in " " + apoi["last"] or " m " not in apoi["last"] + " ":
        bad.append("the last plot shows no range with its unit: %s" % apoi["last"])
numbered = sum(s["messages"] for s in d["senders"])
if numbered != sum(c["messages"] for c in d["channels"]) or any(s["lost"] < 0 for s in d["senders"]):
    bad.append("senders' messages %d != channels' %d" % (numbered, sum(c["messages"] for c in d["channels"])))
if bad:
    print("FAIL: " + "; ".join(bad))
    sys.exit(1)
print("check_spy: %d channels, PRL_APOI %.1f/s, lost %d" % (len(ch), apoi["mean_rate_hz"], sum(s["lost"] for s in d["senders"])))
PY

#!/bin/bash
# ctest spy.text_view: scripts/spy without a display shows the terminal view (scripts/spy_text.py).
# Inside a private network namespace (unshare -n: no traffic leaves the machine), a real-time
# paper run at 20x is watched for 6 s while lcm-logger records the same traffic: every data
# channel is decoded by its project type; the rates the view reports for the radar's plots
# (prl.period_s 1 s), the nav solution (snsins.link_period_s 0.5 s) and the aircraft truth
# (trajectory.step_s 0.25 s) are within 5 % of the configured rates x 20 and within 5 % of the
# rates in the recorded log over the same span (and the counts agree within 2 messages: the
# view's first and last message against the log's clock); the last plot's range is shown with
# its unit, and every message the senders numbered is counted on a channel. Options: --text and
# --gui exclude each other; --duration is checked.
# Usage: check_spy.sh SOURCE_DIR BUILD_DIR
. "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"  # SRC, RNAV_BUILD, T, fail, in_private_net

# (joining a multicast group sends an IGMP report: only inside the private namespace)
out=$(in_private_net 'DISPLAY= "$0/scripts/spy" --duration 1' "$SRC" 2>&1) ||
  fail "the headless view failed: $out"
grep -q "^spy: 0 channel(s)" <<<"$out" || fail "without DISPLAY the terminal view did not run: $out"
DISPLAY=:99 "$SRC/scripts/spy" --text --gui >/dev/null 2>&1 && fail "--text --gui accepted"
DISPLAY= "$SRC/scripts/spy" --duration -1 >/dev/null 2>&1 && fail "--duration -1 accepted"

in_private_net '
  lcm-logger --lcm-url="udpm://239.255.76.67:7667?ttl=0" -q "$1/rec.lcmlog" >/dev/null 2>&1 & logger=$!
  "$0/scripts/run" paper --realtime --speed 20 --realizations 1 --net host --no-plots --out "$1/run" \
    --set prl.period_s=1 --set snsins.link_period_s=0.5 --set trajectory.step_s=0.25 >"$1/run.log" 2>&1 &
  run=$!
  DISPLAY= "$0/scripts/spy" --duration 6 --json "$1/spy.json" >"$1/spy.txt" 2>&1
  wait $run; kill -INT $logger; wait $logger' "$SRC" "$T"
[[ -s $T/spy.json ]] || { cat "$T/spy.txt" "$T/run.log"; fail "no spy.json"; }
# --net host: the run warns that its traffic is on the host's network
grep -q "^run: warning: the run's LCM traffic is on this host's network" "$T/run.log" ||
  { cat "$T/run.log"; fail "--net host gave no warning that other users can see the run"; }
PYTHONPATH="$SRC/loggers" /usr/bin/python3 - "$T/spy.json" "$T/rec.lcmlog" <<'PY' || { tail -15 "$T/spy.txt"; exit 1; }
import json, sys
from rnav import lcmlog
d = json.load(open(sys.argv[1]))
ch = {c["channel"]: c for c in d["channels"]}
bad = []
for name, typ in (("PRL_APOI", "prl_plot_t"), ("PRL_TOI", "prl_plot_t"), ("TRUTH_AIRCRAFT", "aircraft_state_t"),
                  ("NAV_SOLUTION", "nav_solution_t"), ("SIM_WINDOW", "sim_window_t"), ("SIM_ACK", "node_ack_t")):
    if ch.get(name, {}).get("type") != typ:
        bad.append("%s: type %s, not %s" % (name, ch.get(name, {}).get("type"), typ))
# the recorded log: per channel, the distinct messages received in the view's span of it
events = {}
for e in lcmlog.events(sys.argv[2]):
    events.setdefault(e.channel, []).append((e.utime * 1e-6, bytes(e.data)))
SPEED, TOL = 20, 0.05
for name, hz in (("PRL_APOI", 1.0), ("NAV_SOLUTION", 2.0), ("TRUTH_AIRCRAFT", 4.0)):
    c = ch.get(name)
    if not c:
        continue
    want = hz * SPEED
    if abs(c["active_rate_hz"] / want - 1) > TOL:
        bad.append("%s: the view reports %.2f/s, configured %.0f/s (%g Hz x %d)" % (name, c["active_rate_hz"], want, hz, SPEED))
    seen, times = set(), []
    for t, data in events.get(name, []):
        if c["first_unix_s"] - 0.02 <= t <= c["last_unix_s"] + 0.02 and data not in seen:
            seen.add(data)
            times.append(t)
    if len(times) < 2:
        bad.append("%s: the recorded log has %d messages in the view's span" % (name, len(times)))
        continue
    log_rate = (len(times) - 1) / (times[-1] - times[0])
    if abs(c["active_rate_hz"] / log_rate - 1) > TOL:
        bad.append("%s: the view reports %.2f/s, the recorded log %.2f/s" % (name, c["active_rate_hz"], log_rate))
    if abs((c["messages"] - c["repeats"]) - len(times)) > 2:
        bad.append("%s: the view counted %d distinct messages, the log %d in the same span"
                   % (name, c["messages"] - c["repeats"], len(times)))
    print("check_spy: %s %.2f/s in the view, %.2f/s in the log, configured %.0f/s" % (name, c["active_rate_hz"], log_rate, want))
apoi = ch.get("PRL_APOI")
if apoi:
    if " range_m=" not in " " + apoi["last"] or " m " not in apoi["last"] + " ":
        bad.append("the last plot shows no range with its unit: %s" % apoi["last"])
numbered = sum(s["messages"] for s in d["senders"])
if numbered != sum(c["messages"] for c in d["channels"]) or any(s["lost"] < 0 for s in d["senders"]):
    bad.append("senders' messages %d != channels' %d" % (numbered, sum(c["messages"] for c in d["channels"])))
if bad:
    print("FAIL: " + "; ".join(bad))
    sys.exit(1)
print("check_spy: %d channels, lost %d" % (len(ch), sum(s["lost"] for s in d["senders"])))
PY

#!/bin/bash
# ctest spy.text_view: scripts/spy without a display shows the terminal view (scripts/spy_text.py).
# Inside a private network namespace (unshare -n: no traffic leaves the machine), a real-time
# paper run at 20x is watched for 6 s (then stopped) while lcm-logger records the same traffic:
# every data channel is decoded by its project type; the rates the view reports for the radar's plots
# (prl.period_s 1 s), the nav solution (snsins.link_period_s 0.5 s) and the aircraft truth
# (trajectory.step_s 0.25 s) are within 5 % of the configured rates x 20 and within 5 % of the
# rates in the recorded log over the same span (from the log's copy of the view's first message to
# its copy of the view's last, found by their BLAKE2b digests); the view counts every message the
# run published in that span (their validity times, utime, step by the configured period) and the
# log holds no message the view missed; the last plot's range is shown with
# its unit, and every message the senders numbered is counted on a channel. Options: --text and
# --gui exclude each other; --duration is checked.
# Usage: check_spy.sh SOURCE_DIR BUILD_DIR
. "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"  # SRC, RNAV_BUILD, T, fail, in_private_net

# (joining a multicast group sends an IGMP report: only inside the private namespace)
out=$(in_private_net 'DISPLAY= "$0/scripts/spy" --host --duration 1' "$SRC" 2>&1) ||
  fail "the headless view failed: $out"
grep -q "^spy: 0 channel(s)" <<<"$out" || fail "without DISPLAY the terminal view did not run: $out"
DISPLAY=:99 "$SRC/scripts/spy" --text --gui >/dev/null 2>&1 && fail "--text --gui accepted"
DISPLAY= "$SRC/scripts/spy" --host --duration -1 >/dev/null 2>&1 && fail "--duration -1 accepted"

in_private_net '
  lcm-logger --lcm-url="udpm://239.255.76.67:7667?ttl=0" -q "$1/rec.lcmlog" >/dev/null 2>&1 & logger=$!
  "$0/scripts/run" paper --realtime --speed 20 --realizations 1 --net host --no-plots --out "$1/run" \
    --set prl.period_s=1 --set snsins.link_period_s=0.5 --set trajectory.step_s=0.25 >"$1/run.log" 2>&1 &
  run=$!
  DISPLAY= "$0/scripts/spy" --host --duration 6 --json "$1/spy.json" >"$1/spy.txt" 2>&1
  # the view has what it needs: the rest of the flight (about 20 s more at 20x, with this test
  # alone on the machine) is not waited for; the logger is stopped after the run
  kill -TERM $run 2>/dev/null; wait $run; sleep 0.2; kill -INT $logger; wait $logger' "$SRC" "$T"
[[ -s $T/spy.json ]] || { cat "$T/spy.txt" "$T/run.log"; fail "no spy.json"; }
# --net host: the run warns that its traffic is on the host's network
grep -q "^run: warning: the run's LCM traffic is on this host's network" "$T/run.log" ||
  { cat "$T/run.log"; fail "--net host gave no warning that other users can see the run"; }
PYTHONPATH="$SRC/scripts" /usr/bin/python3 - "$T/spy.json" "$T/rec.lcmlog" <<'PY' || { tail -15 "$T/spy.txt"; exit 1; }
import hashlib, json, sys
from rnav import lcmlog
d = json.load(open(sys.argv[1]))
ch = {c["channel"]: c for c in d["channels"]}
bad = []
for name, typ in (("PRL_APOI", "prl_plot_t"), ("PRL_TOI", "prl_plot_t"), ("TRUTH_AIRCRAFT", "aircraft_state_t"),
                  ("NAV_SOLUTION", "nav_solution_t"), ("SIM_WINDOW", "sim_window_t"), ("SIM_ACK", "node_ack_t")):
    if ch.get(name, {}).get("type") != typ:
        bad.append("%s: type %s, not %s" % (name, ch.get(name, {}).get("type"), typ))
# the recorded log: per channel, its messages in order of arrival
events = {}
for e in lcmlog.events(sys.argv[2]):
    events.setdefault(e.channel, []).append((e.utime * 1e-6, bytes(e.data)))
types = lcmlog.message_types()
SPEED, TOL = 20, 0.05
# channel, configured rate [Hz of run time], spacing of consecutive messages' utime [us]
for name, hz, step_us in (("PRL_APOI", 1.0, 1000000), ("NAV_SOLUTION", 2.0, 500000), ("TRUTH_AIRCRAFT", 4.0, 250000)):
    c = ch.get(name)
    if not c:
        continue
    want = hz * SPEED
    if abs(c["active_rate_hz"] / want - 1) > TOL:
        bad.append("%s: the view reports %.2f/s, configured %.0f/s (%g Hz x %d)" % (name, c["active_rate_hz"], want, hz, SPEED))
    # the view's span in the log: from the log's copy of the view's first message (by its digest)
    # to its copy of the view's last
    digests = [hashlib.blake2b(data, digest_size=16).hexdigest() for _, data in events.get(name, [])]
    if c["first_blake2b"] not in digests or c["last_blake2b"] not in digests:
        bad.append("%s: the view's first or last message is not in the recorded log" % name)
        continue
    i0 = digests.index(c["first_blake2b"])
    i1 = digests.index(c["last_blake2b"], i0)
    seen, times = set(), []
    for (t, data), digest in zip(events[name][i0:i1 + 1], digests[i0:i1 + 1]):
        if digest not in seen:
            seen.add(digest)
            times.append(t)
    if len(times) < 2:
        bad.append("%s: the recorded log has %d messages in the view's span" % (name, len(times)))
        continue
    # what the run published in that span: one message per step of its validity time
    first, last = (types[events[name][i][1][:8]].decode(events[name][i][1]) for i in (i0, i1))
    published = (last.utime - first.utime) // step_us + 1
    distinct = c["messages"] - c["repeats"]
    if distinct != published:
        bad.append("%s: the view counted %d distinct messages, the run published %d in its span" % (name, distinct, published))
    # lcm-logger drops messages on a loaded machine (seen with three busy loops on two cores), so
    # the log may hold fewer; never more, and its rate is the same within TOL
    if len(times) > distinct:
        bad.append("%s: the log holds %d distinct messages in the view's span, the view %d" % (name, len(times), distinct))
    log_rate = (len(times) - 1) / (times[-1] - times[0])
    if abs(c["active_rate_hz"] / log_rate - 1) > TOL:
        bad.append("%s: the view reports %.2f/s, the recorded log %.2f/s" % (name, c["active_rate_hz"], log_rate))
    print("check_spy: %s %.2f/s in the view, %.2f/s in the log, configured %.0f/s; %d distinct messages in the view, "
          "%d published, %d in the log" % (name, c["active_rate_hz"], log_rate, want, distinct, published, len(times)))
apoi = ch.get("PRL_APOI")
if apoi:
    if " range_m=" not in " " + apoi["last"] or " m " not in apoi["last"] + " ":
        bad.append("the last plot shows no range with its unit: %s" % apoi["last"])
numbered = sum(s["messages"] for s in d["senders"])
if numbered != sum(c["messages"] for c in d["channels"]) or any(s["lost"] < 0 for s in d["senders"]):
    bad.append("senders' messages %d != channels' %d" % (numbered, sum(c["messages"] for c in d["channels"])))
if bad:
    print("FAIL: " + "; ".join(bad) + " (the view lost %d by LCM sequence gaps)" % sum(s["lost"] for s in d["senders"]))
    sys.exit(1)
print("check_spy: %d channels, lost %d" % (len(ch), sum(s["lost"] for s in d["senders"])))
PY

#!/bin/bash
# ctest run.foreign_traffic: another run's traffic replayed into a run on the same network leaves
# its results byte-identical, and run_events.json counts what was ignored.
# Inside a private network namespace (unshare -n: nothing leaves the machine): run A (seed 2) is
# recorded with lcm-logger; run B (seed 1, 10 realizations, --net host: the namespace's own network) runs while
# lcm-logplayer replays A's every channel, control and data, over and over, at its recorded pace; B's table2.json,
# stats_time.csv, stats_range.csv and realizations.csv must equal, byte for byte, those of run C
# (seed 1, in one process, no foreign traffic), and B's run_events.json must report the foreign
# messages it ignored (A's replay runs during all of B's; how many arrive depends on the pace, so
# the check is that some were counted, and the count is printed). B's own LCM log, which heard
# the replay too, is refused by the diagnosis's log reader and by rnav.read_log, naming the two runs.
# Usage: check_foreign_run.sh SOURCE_DIR BUILD_DIR
. "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"  # SRC, RNAV_BUILD, T, fail, in_private_net

in_private_net '
  url="udpm://239.255.76.67:7667?ttl=0"
  "$0/scripts/run" paper --realizations 2 --seed 2 --net host --no-plots --lcm-log "$1/a.lcmlog" --out "$1/a" >"$1/a.log" 2>&1 || exit 8
  ( while true; do lcm-logplayer --lcm-url="$url" "$1/a.lcmlog" >/dev/null 2>&1; done ) & player=$!
  sleep 0.2
  "$0/scripts/run" paper --realizations 10 --seed 1 --net host --no-plots --lcm-log "$1/b.lcmlog" --out "$1/b" >"$1/b.log" 2>&1; rc=$?
  pkill -P $player 2>/dev/null; kill $player 2>/dev/null; wait
  exit $rc' "$SRC" "$T"
rc=$?
((rc != 8)) || { tail -5 "$T/a.log"; fail "run A failed"; }
((rc == 0)) || { tail -15 "$T/b.log"; fail "run B failed (exit $rc) with another run's traffic replayed into its network"; }
"$SRC/scripts/run" paper --realizations 10 --seed 1 --inproc --no-plots --out "$T/c" >"$T/c.log" 2>&1 || { tail -5 "$T/c.log"; fail "run C failed"; }
for f in table2.json stats_time.csv stats_range.csv realizations.csv; do
  cmp -s "$T/b/$f" "$T/c/$f" || fail "$f differs between the run with another run's traffic and the run without"
done
n=$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["foreign_messages_ignored"]["total"])' "$T/b/run_events.json") ||
  fail "run_events.json has no foreign_messages_ignored"
((n > 0)) || fail "run_events.json counts no foreign message ignored; the replay sent A's thousands during B's run"
grep -q "message(s) of another run on this network ignored" "$T/b/logs/clock.log" || fail "the clock did not say it ignored another run's messages"
# B's own recording heard A's replay too: a log of two runs is refused by its reader, naming both.
"$RNAV_BUILD/bin/rnav_diagnose" prl "$T/b.lcmlog" --injections 0 >"$T/d.out" 2>"$T/d.err"; rc=$?
((rc == 2)) && grep -q "b.lcmlog: the log holds the traffic of 2 runs (run ids " "$T/d.err" ||
  fail "diagnosing a log of two runs: exit $rc, expected 2 and the two runs named: $(tail -2 "$T/d.err")"
PYTHONPATH="$SRC/scripts" /usr/bin/python3 -m rnav show "$T/b.lcmlog" >"$T/p.out" 2>"$T/p.err"; rc=$?
((rc == 2)) && grep -q "b.lcmlog: the log holds the traffic of 2 runs (run ids " "$T/p.err" ||
  fail "python3 -m rnav show of a log of two runs: exit $rc, expected 2 and the two runs named: $(tail -2 "$T/p.err")"
echo "check_foreign_run: results byte-identical with another run's traffic replayed; $n foreign messages ignored"

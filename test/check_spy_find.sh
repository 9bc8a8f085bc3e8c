#!/bin/bash
# ctest spy.find_run: scripts/spy finds the run. In a private network namespace (unshare -n: no
# traffic leaves the machine), with a runs folder of its own (RNAV_RUNS_DIR): bare scripts/spy
# with no run up says so in one line and exits 1; with one real-time run up (in its own private
# namespace, inside this one) it joins it and decodes its channels; with two up it lists both
# pids and says how to pick one (--run PID), exit 2, and --run PID watches that one; a run killed
# with SIGKILL leaves its file, which is ignored (the live run is found alone), and a run that
# ends removes its own. scripts/spy --gui without a display (DISPLAY unset, or naming no server) is
# one line pointing to --text, no Java stack trace; scripts/run --realtime --spy without a display
# shows the terminal view on its stdout.
# Usage: check_spy_find.sh SOURCE_DIR BUILD_DIR
. "$(dirname "${BASH_SOURCE[0]}")/check_lib.sh"  # SRC, RNAV_BUILD, T, fail, in_private_net
export RNAV_RUNS_DIR=$T/runs DISPLAY=

# one line on stderr, nothing else, exit status $2; the line holds every later argument
one_line() {
  local what=$1 want=$2 rc=$3 err=$4 s; shift 4
  ((rc == want)) || fail "$what: exit status $rc, expected $want: $(cat "$err")"
  (($(wc -l <"$err") == 1)) || fail "$what: expected one line on stderr, got: $(cat "$err")"
  for s in "$@"; do grep -qF -- "$s" "$err" || fail "$what: '$s' not in: $(cat "$err")"; done
}

in_private_net '
  cd "$0"
  timeout 20 scripts/spy --duration 2 >"$1/none.out" 2>"$1/none.err"; echo $? >"$1/none.rc"
  timeout 20 scripts/spy --gui >"$1/gui.out" 2>"$1/gui.err"; echo $? >"$1/gui.rc"
  DISPLAY=:9999 timeout 60 scripts/spy --gui --host >"$1/gui2.out" 2>"$1/gui2.err"; echo $? >"$1/gui2.rc"
  # a and b at 40 x real time (about 12 s: a outlives the three spy sessions below); c at 100 x
  # (about 6 s: its terminal view prints once a second)
  start() { scripts/run paper --realtime --speed 40 --realizations 1 --no-plots --out "$1/$2" >"$1/$2.log" 2>&1 & }
  start "$1" a; A=$!
  start "$1" b; B=$!
  echo "$A $B" >"$1/pids"
  for _ in $(seq 100); do [[ -f $RNAV_RUNS_DIR/$A.run && -f $RNAV_RUNS_DIR/$B.run ]] && break; sleep 0.1; done
  timeout 20 scripts/spy --duration 2 >"$1/two.out" 2>"$1/two.err"; echo $? >"$1/two.rc"
  timeout 20 scripts/spy --run "$B" --duration 2 --json "$1/b.json" >"$1/b.out" 2>"$1/b.err"
  kill -KILL "$B"; wait "$B" 2>/dev/null
  [[ -f $RNAV_RUNS_DIR/$B.run ]] && touch "$1/b_left_its_file"
  timeout 20 scripts/spy --duration 2 --json "$1/a.json" >"$1/a.out" 2>"$1/a.err"
  wait "$A"; echo $? >"$1/a.rc"
  ls "$RNAV_RUNS_DIR" >"$1/left"
  timeout 20 scripts/spy --duration 2 >/dev/null 2>"$1/after.err"; echo $? >"$1/after.rc"
  scripts/run paper --realtime --speed 100 --realizations 1 --no-plots --spy --out "$1/c" >"$1/c.out" 2>"$1/c.err"
  echo $? >"$1/c.rc"
' "$SRC" "$T"

one_line "spy with no run up" 1 "$(cat "$T/none.rc")" "$T/none.err" "no run is up" "--host"
[[ -s $T/none.out ]] && fail "spy with no run up printed a view: $(head -3 "$T/none.out")"
one_line "spy --gui without DISPLAY" 2 "$(cat "$T/gui.rc")" "$T/gui.err" "--gui needs a display" "--text"
one_line "spy --gui with DISPLAY=:9999 (no server)" 1 "$(cat "$T/gui2.rc")" "$T/gui2.err" "cannot open the display" "--text"
grep -q "Exception" "$T/gui.err" "$T/gui2.err" && fail "a Java exception was printed"
read -r A B <"$T/pids"
# two runs: both listed, how to pick one
(($(cat "$T/two.rc") == 2)) || fail "spy with two runs up: exit status $(cat "$T/two.rc"): $(cat "$T/two.err")"
grep -qF -- "--run PID" "$T/two.err" && grep -q "pid $A: paper" "$T/two.err" && grep -q "pid $B: paper" "$T/two.err" ||
  fail "spy with two runs up does not list both ($A, $B) and --run PID: $(cat "$T/two.err")"
# the run's channels decoded, each way it was found
channels() {
  /usr/bin/python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); print(" ".join(sorted(c["channel"] for c in d["channels"] if c["messages"] > 0)))' "$1" 2>/dev/null
}
for x in b a; do
  got=$(channels "$T/$x.json")
  for ch in PRL_APOI TRUTH_AIRCRAFT NAV_SOLUTION SIM_WINDOW; do
    [[ " $got " == *" $ch "* ]] || fail "spy on run $x: no $ch message (channels: ${got:-none}; $(cat "$T/$x.err"))"
  done
done
grep -q "watching pid $B: paper" "$T/b.err" || fail "spy --run $B does not name the run: $(cat "$T/b.err")"
[[ -f $T/b_left_its_file ]] || fail "the SIGKILLed run left no file (the stale case was not tested)"
grep -q "watching pid $A: paper" "$T/a.err" || fail "spy with run $A up and $B killed did not watch $A: $(cat "$T/a.err")"
(($(cat "$T/a.rc") == 0)) || fail "run a failed: $(tail -3 "$T/a.log")"
[[ ! -s $T/left ]] || fail "files left in the runs folder after the runs ended: $(cat "$T/left")"
one_line "spy after the runs ended" 1 "$(cat "$T/after.rc")" "$T/after.err" "no run is up"
# --spy without a display: the terminal view on the run's stdout
(($(cat "$T/c.rc") == 0)) || fail "run --spy failed: $(tail -3 "$T/c.err")"
grep -qE "^spy: [1-9][0-9]* channel\(s\)" "$T/c.out" && grep -q "^PRL_APOI " "$T/c.out" ||
  fail "run --realtime --spy without a display showed no terminal view on stdout: $(head -5 "$T/c.out"); logs: $(ls "$T/c/logs")"
echo "check_spy_find: ok"

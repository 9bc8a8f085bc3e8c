#!/usr/bin/env bash
# The command-line conventions of every program (ctest cli.*):
#   help    every binary in BUILD/bin and every program in scripts/ (both folders listed, so a new
#           one cannot escape) answers --help and -h with exit 0, usage on stdout starting with
#           "Usage:" or "usage:", nothing on stderr; a program with an option table (it answers
#           --list-options) shows every option its parser accepts in its help, rejects an unknown
#           option with exactly one "PROGRAM: error: unknown option ..." line and exit 2, and
#           names the option a misspelling (two adjacent letters swapped) meant.
#   errors  did-you-mean for a scenario key, a scenario value, an option and a scenario name;
#           --speed and --spy without --realtime; one error prefix where a script relays a
#           binary's error.
#   collected  every error of one command named at once, in one line: unknown keys in two
#           sections of a scenario file and of --set (rnav_clock, scripts/run); two unknown options
#           of a bash script, a binary and a Python program; missing required options of a binary
#           and of a node; scripts/diagnose's missing KIND (and the INPUT that does not exist).
# Usage: check_cli.sh help|errors|collected SOURCE_DIR BUILD_DIR
set -uo pipefail
MODE=$1 SRC=$2 BUILD=$3
export RNAV_BUILD=$BUILD
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
FAILS=0
fail() { echo "FAIL: $*"; FAILS=$((FAILS + 1)); }

# Run "$@" with a time limit; stdout, stderr and status in $TMP/out, $TMP/err, $RC.
run() { timeout 60 "$@" >"$TMP/out" 2>"$TMP/err" </dev/null; RC=$?; }

# The one error line: exactly one line on stderr, "PROG: error: " once, and it starts with it.
check_error_line() {
  local prog=$1 what=$2
  local lines
  lines=$(wc -l <"$TMP/err")
  ((lines == 1)) || { fail "$what: stderr has $lines lines, expected one: $(cat "$TMP/err")"; return; }
  grep -q "^$prog: error: " "$TMP/err" || fail "$what: stderr does not start with '$prog: error: ': $(cat "$TMP/err")"
  (($(grep -o ': error: ' "$TMP/err" | wc -l) == 1)) || fail "$what: 'error:' more than once: $(cat "$TMP/err")"
}

# A long option with two adjacent letters of its name swapped (one edit away).
misspell() {
  local o=$1 i=$((${#1} / 2))
  # Not at a doubled letter (swapping "nn" in --channels would change nothing).
  while ((i + 2 < ${#o})) && [[ ${o:i:1} == "${o:i+1:1}" ]]; do i=$((i + 1)); done
  echo "${o:0:i}${o:i+1:1}${o:i:1}${o:i+2}"
}

check_help() {
  local programs=() f
  for f in "$BUILD"/bin/*; do [[ -f $f && -x $f ]] && programs+=("$f"); done
  ((${#programs[@]} >= 10)) || fail "only ${#programs[@]} binaries in $BUILD/bin"
  for f in "$SRC"/scripts/*; do
    [[ -f $f ]] || continue
    if [[ -x $f ]]; then
      programs+=("$f")
    elif head -c 2 "$f" | grep -q '#!'; then
      fail "$f starts with #! but is not executable (a program the help test would miss)"
    fi
  done
  echo "checking ${#programs[@]} programs"
  for f in "${programs[@]}"; do
    local prog=${f##*/} help
    for h in --help -h; do
      run "$f" "$h"
      ((RC == 0)) || fail "$prog $h: exit status $RC"
      [[ -s $TMP/err ]] && fail "$prog $h: wrote to stderr: $(head -n 3 "$TMP/err")"
      head -n 1 "$TMP/out" | grep -qE '^(Usage|usage): ' || fail "$prog $h: stdout does not start with Usage: ($(head -n 1 "$TMP/out"))"
    done
    help=$(cat "$TMP/out")
    # A program with an option table offers --list-options; every option it accepts must be in
    # its help. (One without, e.g. scripts/test, passes its arguments on: it is not probed.)
    grep -q -- '^  --list-options' <<<"$help" || continue
    run "$f" --list-options
    ((RC == 0)) || { fail "$prog: its help offers --list-options, which fails ($RC)"; continue; }
    local names=() longest="" n
    while read -r n _; do [[ -n $n ]] && names+=("$n"); done <"$TMP/out"
    for n in "${names[@]}"; do
      grep -qE -- "(^|[^a-z-])$n([^a-z-]|\$)" <<<"$help" || fail "$prog: option $n is accepted but not in its help"
      [[ $n == --* && ${#n} -gt ${#longest} && $n != --list-options ]] && longest=$n
    done
    run "$f" --no-such-option-x
    ((RC == 2)) || fail "$prog --no-such-option-x: exit status $RC, expected 2"
    check_error_line "$prog" "$prog --no-such-option-x"
    grep -q "unknown option '--no-such-option-x'" "$TMP/err" || fail "$prog: unknown option not named: $(cat "$TMP/err")"
    if [[ -n $longest ]]; then
      local typo
      typo=$(misspell "$longest")
      run "$f" "$typo"
      ((RC == 2)) || fail "$prog $typo: exit status $RC, expected 2"
      check_error_line "$prog" "$prog $typo"
      grep -qF "did you mean '$longest'?" "$TMP/err" || fail "$prog $typo: no 'did you mean '$longest'?': $(cat "$TMP/err")"
    fi
  done
}

check_errors() {
  local RUN=$SRC/scripts/run BIN=$BUILD/bin
  local out=$TMP/never   # no case below may write it
  # A scenario key: through the binary and through scripts/run (relayed with one prefix).
  run "$BIN/rnav_clock" --scenario "$SRC/sim/scenarios/paper.json" --set radar.x_n=1 --check
  ((RC == 2)) || fail "rnav_clock radar.x_n: exit status $RC"
  check_error_line rnav_clock "rnav_clock radar.x_n"
  grep -qF "radar.x_n (did you mean 'radar.x_m'?)" "$TMP/err" || fail "rnav_clock: no did-you-mean for radar.x_n: $(cat "$TMP/err")"
  run "$RUN" paper --inproc --set radar.x_n=1 --out "$out"
  ((RC == 2)) || fail "run radar.x_n: exit status $RC"
  check_error_line run "run radar.x_n"
  grep -qF "did you mean 'radar.x_m'?" "$TMP/err" || fail "run: no did-you-mean for radar.x_n: $(cat "$TMP/err")"
  run "$BIN/rnav_inproc" --scenario "$SRC/sim/scenarios/uav.json" --set uav.path=circel
  ((RC == 2)) || fail "rnav_inproc uav.path=circel: exit status $RC"
  grep -qF "did you mean 'circle'?" "$TMP/err" || fail "rnav_inproc: no did-you-mean for circel: $(cat "$TMP/err")"
  # A key far from every known one gets no guess.
  run "$BIN/rnav_clock" --scenario "$SRC/sim/scenarios/paper.json" --set radar.zzzzzzzz=1 --check
  grep -q "unknown scenario key(s): radar.zzzzzzzz" "$TMP/err" && ! grep -q "did you mean" "$TMP/err" ||
    fail "rnav_clock radar.zzzzzzzz: $(cat "$TMP/err")"
  # A scenario name and an option of scripts/run.
  run "$RUN" pape --out "$out"
  ((RC == 2)) || fail "run pape: exit status $RC"
  check_error_line run "run pape"
  grep -qF "unknown scenario 'pape' (did you mean 'paper'?)" "$TMP/err" || fail "run pape: $(cat "$TMP/err")"
  run "$RUN" paper --realisations 3 --out "$out"
  check_error_line run "run --realisations"
  grep -qF "did you mean '--realizations'?" "$TMP/err" || fail "run --realisations: $(cat "$TMP/err")"
  # --speed and --spy need --realtime (scripts/run and rnav_clock).
  run "$RUN" paper --speed 10 --out "$out"
  ((RC == 2)) || fail "run --speed without --realtime: exit status $RC"
  check_error_line run "run --speed"
  grep -qF -- "--speed applies only with --realtime" "$TMP/err" || fail "run --speed: $(cat "$TMP/err")"
  run "$RUN" paper --spy --out "$out"
  ((RC == 2)) || fail "run --spy without --realtime: exit status $RC"
  grep -qF -- "--spy applies only with --realtime" "$TMP/err" || fail "run --spy: $(cat "$TMP/err")"
  run "$BIN/rnav_clock" --scenario "$SRC/sim/scenarios/paper.json" --nodes prl --speed 10
  ((RC == 2)) || fail "rnav_clock --speed without --realtime: exit status $RC"
  check_error_line rnav_clock "rnav_clock --speed"
  [[ -e $out ]] && fail "a rejected command wrote $out"
  # A node no longer ignores an option it does not know.
  run "$BIN/rnav_prl" --scenario "$SRC/sim/scenarios/paper.json" --lcm-ur x
  ((RC == 2)) || fail "rnav_prl --lcm-ur: exit status $RC"
  grep -qF "did you mean '--lcm-url'?" "$TMP/err" || fail "rnav_prl --lcm-ur: $(cat "$TMP/err")"
}

# Every string after the program's name must be in its one error line (exit status 2).
expect_all() {
  local prog=$1 what=$2 s; shift 2
  ((RC == 2)) || fail "$what: exit status $RC, expected 2 ($(cat "$TMP/err"))"
  check_error_line "$prog" "$what"
  for s in "$@"; do grep -qF -- "$s" "$TMP/err" || fail "$what: '$s' not named: $(cat "$TMP/err")"; done
}

check_collected() {
  local RUN=$SRC/scripts/run BIN=$BUILD/bin out=$TMP/never
  # a scenario file with unknown keys in two sections and at the top
  printf '{"radar": {"x_n": -1200}, "prl": {"bias_rang_m": 2}, "nmae": "x"}\n' >"$TMP/two.json"
  local keys=("radar.x_n (did you mean 'radar.x_m'?)" "prl.bias_rang_m (did you mean 'prl.bias_range_m'?)" "nmae")
  run "$BIN/rnav_clock" --scenario "$TMP/two.json" --check
  expect_all rnav_clock "rnav_clock --check of a file with three unknown keys" "${keys[@]}"
  run "$RUN" "$TMP/two.json" --inproc --out "$out"
  expect_all run "run of a file with three unknown keys" "${keys[@]}"
  run "$BIN/rnav_clock" --scenario "$SRC/sim/scenarios/paper.json" --set radar.x_n=1 --set prl.bias_rang_m=2 --check
  expect_all rnav_clock "rnav_clock --set of two unknown keys" "${keys[@]:0:2}"
  # two unknown options: a bash script, a binary, a Python program
  run "$RUN" paper --realisations 3 --sede 2 --out "$out"
  expect_all run "run with two unknown options" "'--realisations' (did you mean '--realizations'?)" "'--sede' (did you mean '--seed'?)"
  run "$BIN/rnav_clock" --scenaro x --nods prl --no-such-option-x
  expect_all rnav_clock "rnav_clock with three unknown options" "'--scenaro' (did you mean '--scenario'?)" \
    "'--nods' (did you mean '--nodes'?)" "'--no-such-option-x'"
  run /usr/bin/python3 "$SRC/scripts/spy_text.py" --no-such-option-x --durtion 1
  expect_all spy_text.py "spy_text.py with two unknown options" "'--no-such-option-x'" "'--durtion' (did you mean '--duration'?)"
  # missing required options, all named
  run "$BIN/rnav_clock"
  expect_all rnav_clock "rnav_clock without options" "--scenario FILE and --nodes a,b,c are required"
  run "$BIN/rnav_logger"
  expect_all rnav_logger "rnav_logger without options" "--scenario FILE and --out DIR are required"
  # scripts/diagnose: the missing KIND named (and the INPUT that does not exist), or both missing
  run "$SRC/scripts/diagnose" "$TMP/missing-folder"
  expect_all diagnose "diagnose $TMP/missing-folder" "KIND (prl, uav or multi) is missing" "INPUT '$TMP/missing-folder' does not exist"
  run "$SRC/scripts/diagnose"
  expect_all diagnose "diagnose without arguments" "KIND (prl, uav or multi) and INPUT are missing"
  run "$SRC/scripts/diagnose" prl
  expect_all diagnose "diagnose prl" "INPUT is missing after KIND 'prl'"
  [[ -e $out ]] && fail "a rejected command wrote $out"
}

case $MODE in
  help) check_help ;;
  errors) check_errors ;;
  collected) check_collected ;;
  *) echo "usage: check_cli.sh help|errors|collected SOURCE_DIR BUILD_DIR" >&2; exit 2 ;;
esac
((FAILS == 0)) || { echo "$FAILS failure(s)"; exit 1; }
echo "ok"

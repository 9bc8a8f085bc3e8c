#!/bin/bash
# ctest run.stale_work_folder: the work folder (OUT.partial.XXXXXX) of a scripts/run that was
# SIGKILLed stays behind; the next run of the same OUT removes it, naming it, and leaves alone a
# work folder whose run is still going (its .owner names a live process) and one without .owner.
# Usage: check_run_stale.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$1
export RNAV_BUILD=$2
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
OUT=$T/out

# a run killed with SIGKILL (its whole process group) while it works
setsid "$SRC/scripts/run" paper --inproc --no-plots --realizations 400 --out "$OUT" >"$T/killed.log" 2>&1 &
PGID=$!
for _ in $(seq 300); do compgen -G "$OUT.partial.*/.owner" >/dev/null && break; sleep 0.1; done
compgen -G "$OUT.partial.*/.owner" >/dev/null || { cat "$T/killed.log"; fail "the run never made its work folder"; }
kill -KILL -- "-$PGID"
wait "$PGID" 2>/dev/null
DEAD=$(compgen -G "$OUT.partial.*")
[[ -d $DEAD ]] || fail "the killed run's work folder is gone already (nothing to test)"

# a work folder of a run still going (this shell) and one of an older version (no .owner)
LIVE=$OUT.partial.live00
mkdir "$LIVE" "$OUT.partial.old000"
stat_tail=$(cat /proc/$$/stat); stat_tail=${stat_tail##*) }
echo "$(hostname) $$ $(awk '{print $20}' <<<"$stat_tail")" >"$LIVE/.owner"

"$SRC/scripts/run" paper --inproc --no-plots --realizations 2 --out "$OUT" >"$T/next.log" 2>&1 || { cat "$T/next.log"; fail "the next run failed"; }
[[ ! -e $DEAD ]] || fail "the killed run's work folder $DEAD is still there"
grep -qF "run: removed $DEAD, the work folder of a run that died" "$T/next.log" || { cat "$T/next.log"; fail "the removal is not named"; }
[[ -d $LIVE ]] || fail "the work folder of a run still going was removed"
[[ -d $OUT.partial.old000 ]] || fail "a work folder without .owner was removed"
[[ -f $OUT/table2.json && ! -e $OUT/.owner ]] || fail "the next run's output is not complete, or carries .owner"
echo "check_run_stale: ok"

# How a run makes itself known to scripts/spy (sourced, not run). scripts/run, while its processes
# talk over LCM, keeps a file RUNS_DIR/PID.run naming it: PID is the run's own process, whose
# network namespace (its private one, or this host's) the run's traffic is in. The file is removed
# when the run ends; one left by a run that was killed (SIGKILL, a reset) is stale: its PID is gone
# or is another process now (the start time in the file differs from /proc/PID/stat's), and
# runs_live ignores it and removes it.
#
# RUNS_DIR: $RNAV_RUNS_DIR if set, else $XDG_RUNTIME_DIR/rnav-runs (/tmp/rnav-runs-UID without
# XDG_RUNTIME_DIR), created mode 700; one that another user owns is not used.
#
# A file holds one key=value per line:
#   pid=PID            the run (scripts/run's process id; nsenter -t PID -n joins its network)
#   start=TICKS        PID's start time (/proc/PID/stat field 22), to tell a reused PID apart
#   netns=1|0          1: a private network namespace (join it); 0: this host's network
#   lcm_url=URL        the LCM URL of the run
#   scenario=NAME, realizations=N, realtime=0|1, speed=X, out=DIR, started=ISO-8601 time

# The start time of process $1 (clock ticks since boot), or failure if there is none.
proc_start() { local s; s=$(cat "/proc/$1/stat" 2>/dev/null) || return 1; s=${s##*) }; awk '{print $20}' <<<"$s"; }

runs_dir() {
  if [[ -n ${RNAV_RUNS_DIR:-} ]]; then echo "$RNAV_RUNS_DIR"
  elif [[ -n ${XDG_RUNTIME_DIR:-} ]]; then echo "$XDG_RUNTIME_DIR/rnav-runs"
  else echo "/tmp/rnav-runs-$(id -u)"; fi
}

# runs_advertise FILE key=value...: write the run's file atomically (nothing on failure: a run
# that cannot advertise itself still runs; scripts/spy --netns-pid reaches it).
runs_advertise() {
  local file=$1 dir; shift
  dir=$(dirname "$file")
  (umask 077 && mkdir -p "$dir") 2>/dev/null && [[ -O $dir ]] || return 1
  printf '%s\n' "$@" >"$file.tmp.$$" 2>/dev/null && mv -f "$file.tmp.$$" "$file" 2>/dev/null
}

# runs_live: the files of the runs that are up, one per line, oldest first; stale ones removed.
runs_live() {
  local dir f pid start
  dir=$(runs_dir)
  [[ -d $dir ]] || return 0
  for f in $(ls -tr "$dir" 2>/dev/null); do
    [[ $f == *.run ]] || continue
    f=$dir/$f
    pid=$(sed -n 's/^pid=//p' "$f" 2>/dev/null) start=$(sed -n 's/^start=//p' "$f" 2>/dev/null)
    if [[ $pid =~ ^[1-9][0-9]*$ && -n $start && $(proc_start "$pid") == "$start" ]]; then
      echo "$f"
    else
      rm -f "$f" 2>/dev/null
    fi
  done
}

# runs_get FILE KEY: the value of KEY in a run's file.
runs_get() { sed -n "s/^$2=//p" "$1" | head -n 1; }

# runs_describe FILE: one line about the run, as scripts/spy lists it.
runs_describe() {
  local f=$1 rt=""
  [[ $(runs_get "$f" realtime) == 1 ]] && rt=", real time x$(runs_get "$f" speed)"
  printf 'pid %s: %s, %s realization(s)%s, started %s, %s, out %s\n' "$(runs_get "$f" pid)" \
    "$(runs_get "$f" scenario)" "$(runs_get "$f" realizations)" "$rt" "$(runs_get "$f" started)" \
    "$([[ $(runs_get "$f" netns) == 1 ]] && echo "private network namespace" || echo "this host's network")" \
    "$(runs_get "$f" out)"
}

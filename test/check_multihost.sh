#!/usr/bin/env bash
# ctest multihost.two_namespaces: the documentation's several-hosts recipe ("Networking" in
# docs/processes-and-protocol.md) run as written on two "hosts" — two network namespaces joined
# by a veth pair named eth1 at both ends
# (10.231.0.1 on host A, 10.231.0.2 on host B; besides lo the only link of each) — gives byte for
# byte the statistics of the single-host run (scripts/run with the recipe's scenario,
# realizations and seed).
#
# The recipe is read from the documentation, README.md or a docs/*.md page (the indented block
# starting "# both hosts", in exactly one of them): its "# both hosts" lines run on both hosts
# (variable assignments before every command, other lines such as
# the multicast route once per host), its "# host A" and "# host B" lines start one process each
# on that host. The commands run unchanged in a scratch folder holding `sim` and `build` as links
# to SOURCE_DIR/sim and BUILD_DIR. Before the run, a probe datagram must cross the veth both ways
# (multicast with the recipe's group, port and ttl=1); after it, the veth's packet counters show
# the run's traffic crossed it. Every process must exit 0 within TIMEOUT_S, else the test fails
# naming it (its host, status and last log lines).
#
# Namespaces: `ip netns add` (root); without root, the whole test re-runs itself in a user
# namespace (unshare -Ur) and holds each network namespace with a `sleep` process (unshare -n),
# entered with nsenter. A trap kills every process of the test and removes both namespaces.
# Usage: check_multihost.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
(($# == 2)) || { echo "usage: check_multihost.sh SOURCE_DIR BUILD_DIR" >&2; exit 2; }
SRC=$(cd "$1" && pwd)
BUILD=$(cd "$2" && pwd)
TIMEOUT_S=120
PY=/usr/bin/python3
T_START=$(date +%s.%N)

fail() { echo "FAIL: $*" >&2; exit 1; }
for b in rnav_clock rnav_trajectory rnav_snsins rnav_prl rnav_prl_bias rnav_logger; do
  [[ -x $BUILD/bin/$b ]] || fail "$BUILD/bin/$b missing (build the project first)"
done
command -v ip >/dev/null || fail "needs ip (Debian package iproute2)"
[[ -x $PY ]] || fail "needs $PY"

# ---- The recipe, from the documentation. ----
RECIPE_FILE=""
for doc in "$SRC/README.md" "$SRC"/docs/*.md; do
  [[ -f $doc ]] && grep -q '^    # both hosts' "$doc" || continue
  [[ -z $RECIPE_FILE ]] || fail "two several-hosts recipes (indented blocks starting '# both hosts'): ${RECIPE_FILE#$SRC/} and ${doc#$SRC/}"
  RECIPE_FILE=$doc
done
[[ -n $RECIPE_FILE ]] || fail "neither README.md nor docs/*.md has a several-hosts recipe (an indented block starting '# both hosts')"
declare -a HOST_OF_LINE=() LINES=()
host="" in_block=0 cont=""
while IFS= read -r raw; do
  if ((!in_block)); then
    [[ $raw == "    # both hosts"* ]] || continue
    in_block=1
  fi
  [[ $raw == "    "* ]] || break   # the block ends at its first line that is not indented
  line=${raw:4}
  if [[ $line == *\\ ]]; then cont+="${line%\\} "; continue; fi
  line="$cont$line"; cont=""
  line=$(sed -E 's/^[[:space:]]+//; s/[[:space:]]+$//' <<<"$line")
  case $line in
    "# both hosts"*) host=both ;;
    "# host A"*) host=A ;;
    "# host B"*) host=B ;;
    "#"* | "") ;;
    *) LINES+=("$line"); HOST_OF_LINE+=("$host") ;;
  esac
done <"$RECIPE_FILE"
((in_block)) || fail "${RECIPE_FILE#$SRC/} has no several-hosts recipe (an indented block starting '# both hosts')"

PRELUDE=""
SETUP=() PROCS=() PROC_HOST=() PROC_NAME=()
for i in "${!LINES[@]}"; do
  line=${LINES[$i]} h=${HOST_OF_LINE[$i]}
  if [[ $line =~ ^[A-Za-z_][A-Za-z0-9_]*= ]]; then
    [[ $h == both ]] || fail "recipe line '$line' (${RECIPE_FILE#$SRC/}): assignments belong under '# both hosts'"
    PRELUDE+="$line"$'\n'
  elif [[ $line =~ ^build/bin/rnav_([a-z_]+)[[:space:]] ]]; then
    [[ $h == A || $h == B ]] || fail "recipe line '$line' (${RECIPE_FILE#$SRC/}): a process belongs under '# host A' or '# host B'"
    PROCS+=("$(sed -E 's/[[:space:]]*&$//' <<<"$line")"); PROC_HOST+=("$h"); PROC_NAME+=("${BASH_REMATCH[1]}")
  else
    [[ $h == both ]] || fail "recipe line '$line' (${RECIPE_FILE#$SRC/}): only processes under '# host A' and '# host B'"
    SETUP+=("$line")
  fi
done
# The recipe must really span both hosts: one clock, every node it waits for started once, each
# host running something (a documentation edit that puts everything on one host fails here).
clock_i="" started=()
for i in "${!PROCS[@]}"; do
  if [[ ${PROC_NAME[$i]} == clock ]]; then
    [[ -z $clock_i ]] || fail "the recipe starts rnav_clock twice"
    clock_i=$i
  else
    started+=("${PROC_NAME[$i]}")
  fi
done
[[ -n $clock_i ]] || fail "the recipe starts no rnav_clock"
clock_cmd=${PROCS[$clock_i]}
[[ $clock_cmd =~ --nodes[[:space:]]+([a-z_,]+) ]] || fail "the recipe's rnav_clock has no --nodes"
want=$(tr , '\n' <<<"${BASH_REMATCH[1]}" | sort | tr '\n' ' ')
have=$(printf '%s\n' "${started[@]}" | sort | tr '\n' ' ')
[[ $want == "$have" ]] || fail "the recipe's clock waits for nodes '$want' but it starts '$have'"
[[ " ${PROC_HOST[*]} " == *" A "* && " ${PROC_HOST[*]} " == *" B "* ]] || fail "the recipe does not use both hosts"
[[ $clock_cmd =~ --realizations[[:space:]]+([0-9]+) ]] || fail "the recipe's rnav_clock has no --realizations"
N=${BASH_REMATCH[1]}
[[ $clock_cmd =~ --seed[[:space:]]+(-?[0-9]+) ]] || fail "the recipe's rnav_clock has no --seed"
SEED=${BASH_REMATCH[1]}
logger_out=""
for i in "${!PROCS[@]}"; do
  [[ ${PROC_NAME[$i]} == logger && ${PROCS[$i]} =~ --out[[:space:]]+([^[:space:]]+) ]] && logger_out=${BASH_REMATCH[1]}
done
[[ -n $logger_out ]] || fail "the recipe's rnav_logger has no --out"

# ---- Scratch folder and the two hosts. ----
SCRATCH=$(mktemp -d "${TMPDIR:-/tmp}/rnav_multihost.XXXXXX")
ln -s "$SRC/sim" "$SCRATCH/sim"
ln -s "$BUILD" "$SCRATCH/build"
mkdir "$SCRATCH/logs"
NS_A=rnav_mh_a_$$ NS_B=rnav_mh_b_$$
# Namespaces an earlier test left behind when it was killed outright (SIGKILL, e.g. by ctest's
# timeout; its processes died with it, by their parent-death signal): removed if that test's
# pid is gone (as root only: kill -0 then tells a gone pid from another user's).
if [[ $(id -u) == 0 && ${RNAV_MH_USERNS:-0} != 1 ]]; then
  for ns in $(ip netns list 2>/dev/null | grep -oE '^rnav_mh_[ab]_[0-9]+' || true); do
    kill -0 "${ns##*_}" 2>/dev/null || ip netns del "$ns" 2>/dev/null || true
  done
fi
MODE=""
declare -A REF=() NAME_OF=() HOST=()
BG=()        # every background process of this test, killed by the trap
OK=0
cleanup() {
  local pid
  exec 3>&2 2>/dev/null   # no "Killed" job notices for the processes killed here
  for pid in "${BG[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
  if [[ $MODE == netns ]]; then
    for ns in "$NS_A" "$NS_B"; do
      for pid in $(ip netns pids "$ns" 2>/dev/null); do kill -KILL "$pid" 2>/dev/null || true; done
    done
  fi
  wait 2>/dev/null || true
  ip netns del "$NS_A" 2>/dev/null || true
  ip netns del "$NS_B" 2>/dev/null || true
  if ((OK)); then rm -rf "$SCRATCH"; else echo "check_multihost: logs kept in $SCRATCH/logs" >&3; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# "on A|B COMMAND...": run COMMAND in that host's network namespace. "spawn A|B COMMAND...": the
# same in the background, its pid (ip and nsenter exec COMMAND: the pid is COMMAND's) in SPAWNED.
on() {
  local h=$1; shift
  if [[ $MODE == netns ]]; then ip netns exec "${REF[$h]}" "$@"; else nsenter -t "${REF[$h]}" -n "$@"; fi
}
spawn() {
  local h=$1; shift
  if [[ $MODE == netns ]]; then ip netns exec "${REF[$h]}" "$@" & else nsenter -t "${REF[$h]}" -n "$@" & fi
  SPAWNED=$!; BG+=("$SPAWNED")
}

if [[ $(id -u) == 0 && ${RNAV_MH_USERNS:-0} != 1 ]] && ip netns add "$NS_A" 2>/dev/null; then
  MODE=netns
  ip netns add "$NS_B" || fail "ip netns add $NS_B failed"
  REF[A]=$NS_A REF[B]=$NS_B
elif [[ $(id -u) != 0 ]]; then
  unshare -Ur true 2>/dev/null || fail "needs root (ip netns) or user namespaces (unshare -Ur)"
  echo "check_multihost: not root: running in a user namespace (unshare -Ur)" >&2
  trap - EXIT; rm -rf "$SCRATCH"
  exec unshare -Ur env RNAV_MH_USERNS=1 bash "$0" "$SRC" "$BUILD"
else
  MODE=holder
  for h in A B; do
    setpriv --pdeathsig KILL -- unshare -n sleep infinity &
    BG+=("$!"); REF[$h]=$!
  done
  for h in A B; do   # wait until each holder has its own network namespace
    for _ in $(seq 100); do
      [[ $(readlink "/proc/${REF[$h]}/ns/net") != "$(readlink /proc/self/ns/net)" ]] && break
      sleep 0.05
    done
    [[ $(readlink "/proc/${REF[$h]}/ns/net") != "$(readlink /proc/self/ns/net)" ]] || fail "unshare -n did not make a network namespace"
  done
fi
echo "check_multihost: two hosts = network namespaces ($MODE: A=${REF[A]}, B=${REF[B]}) joined by a veth pair" >&2
on A ip link add eth1 type veth peer name eth1 netns "${REF[B]}" || fail "cannot create the veth pair"
on A ip addr add 10.231.0.1/24 dev eth1
on B ip addr add 10.231.0.2/24 dev eth1
for h in A B; do on "$h" ip link set lo up; on "$h" ip link set eth1 up; done

# ---- The recipe's setup lines (the multicast route), its URL. ----
cd "$SCRATCH"
for h in A B; do
  for line in "${SETUP[@]}"; do
    out=$(on "$h" bash -c "${PRELUDE}${line}" 2>&1) || fail "recipe line '$line' failed on host $h: $out"
  done
done
# shellcheck disable=SC2016  # expanded by the inner bash
URL=$(on A bash -c "${PRELUDE}"'printf %s "${URL:-}"')
[[ $URL =~ ^udpm://([0-9.]+):([0-9]+)\?(.*)$ ]] || fail "the recipe's URL '$URL' is not udpm://GROUP:PORT?OPTIONS"
GROUP=${BASH_REMATCH[1]} PORT=${BASH_REMATCH[2]}
[[ "&${BASH_REMATCH[3]}&" == *"&ttl=1&"* ]] || fail "the recipe's URL '$URL' does not have ttl=1"
echo "check_multihost: URL $URL" >&2

# ---- Multicast must cross the veth both ways (a probe with the recipe's group, port, ttl 1). ----
PROBE='
import socket, struct, sys, time
mode, group, port, want_from = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
if mode == "send":
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 1)
    for _ in range(100):
        s.sendto(b"rnav multihost probe", (group, port)); time.sleep(0.05)
    sys.exit(0)
s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
s.bind(("", port))
try:
    s.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP,
                 struct.pack("4s4s", socket.inet_aton(group), socket.inet_aton("0.0.0.0")))
except OSError as e:
    sys.exit("cannot join %s: %s (no multicast route?)" % (group, e.strerror))
s.settimeout(5)
try:
    while True:
        data, (src, _) = s.recvfrom(100)
        if data == b"rnav multihost probe" and src == want_from:
            sys.exit(0)
except socket.timeout:
    sys.exit("no probe from %s within 5 s" % want_from)
'
declare -A ADDR=([A]=10.231.0.1 [B]=10.231.0.2)
for dir in "A B" "B A"; do
  read -r from to <<<"$dir"
  spawn "$to" "$PY" -c "$PROBE" recv "$GROUP" "$PORT" "${ADDR[$from]}" >"$SCRATCH/logs/probe.log" 2>&1; rx=$SPAWNED
  sleep 0.2
  spawn "$from" "$PY" -c "$PROBE" send "$GROUP" "$PORT" - >/dev/null 2>&1; tx=$SPAWNED
  status=0; wait "$rx" || status=$?
  kill "$tx" 2>/dev/null || true
  ((status == 0)) || fail "multicast to $GROUP:$PORT with ttl=1 does not cross the veth from host $from to host $to: $(tail -n 1 "$SCRATCH/logs/probe.log")"
done
# rx packets and bytes of the host's eth1 (/proc/net/dev: "eth1: RX-bytes RX-packets ...")
read_veth() { on "$1" sed 's/:/ /' /proc/net/dev | awk '$1 == "eth1" { print $3, $2 }'; }
read -r a_rx0 a_by0 <<<"$(read_veth A)"; read -r b_rx0 b_by0 <<<"$(read_veth B)"

# ---- The run: every process of the recipe on its host. ----
echo "check_multihost: the recipe, $N realization(s), seed $SEED: $(for i in "${!PROCS[@]}"; do printf '%s on %s, ' "${PROC_NAME[$i]}" "${PROC_HOST[$i]}"; done | sed 's/, $//')" >&2
T0=$(date +%s.%N)
for i in "${!PROCS[@]}"; do
  n=${PROC_NAME[$i]} h=${PROC_HOST[$i]}
  spawn "$h" setpriv --pdeathsig KILL -- bash -c "${PRELUDE}exec ${PROCS[$i]}" >"$SCRATCH/logs/$n.log" 2>&1 </dev/null
  NAME_OF[$SPAWNED]=$n; HOST[$SPAWNED]=$h
done
sleep "$TIMEOUT_S" & timer=$!; BG+=("$timer")
while ((${#NAME_OF[@]} > 0)); do
  pid="" status=0
  wait -n -p pid "${!NAME_OF[@]}" "$timer" || status=$?
  [[ -n $pid ]] || fail "wait returned no process (status $status)"
  if [[ $pid == "$timer" ]]; then
    still=""
    for p in "${!NAME_OF[@]}"; do still+=", rnav_${NAME_OF[$p]} on host ${HOST[$p]}"; done
    fail "the run did not finish within $TIMEOUT_S s; still running: ${still#, } (the clock's last line: $(tail -n 1 "$SCRATCH/logs/clock.log"))"
  fi
  n=${NAME_OF[$pid]} h=${HOST[$pid]}
  unset "NAME_OF[$pid]"
  if ((status != 0)); then
    echo "check_multihost: last lines of $n's log:" >&2
    tail -n 5 "$SCRATCH/logs/$n.log" | sed 's/^/  | /' >&2
    fail "process rnav_$n on host $h exited with status $status"
  fi
done
kill "$timer" 2>/dev/null || true
T1=$(date +%s.%N)
read -r a_rx a_by <<<"$(read_veth A)"; read -r b_rx b_by <<<"$(read_veth B)"
a_rx=$((a_rx - a_rx0)) b_rx=$((b_rx - b_rx0)) a_by=$((a_by - a_by0)) b_by=$((b_by - b_by0))
awk -v a="$T0" -v b="$T1" -v ab="$b_rx" -v abb="$b_by" -v ba="$a_rx" -v bab="$a_by" 'BEGIN {
  printf "check_multihost: two-host run done in %.1f s; over the veth: A -> B %d packets (%.1f MB), B -> A %d packets (%.1f MB)\n",
    b - a, ab, abb / 1e6, ba, bab / 1e6 }' >&2
((a_rx > 0 && b_rx > 0)) || fail "no packets crossed the veth during the run (A received $a_rx, B $b_rx)"

# ---- The single-host run, and the comparison. ----
# shellcheck disable=SC2016
SCEN_FILE=$(on A bash -c "${PRELUDE}"'printf %s "${S:-}"')
[[ -f $SCEN_FILE ]] || fail "the recipe's scenario S='$SCEN_FILE' is not a file"
[[ $SCEN_FILE == /* ]] || SCEN_FILE=$SRC/${SCEN_FILE#./}
RNAV_BUILD=$BUILD "$SRC/scripts/run" "$SCEN_FILE" --realizations "$N" --seed "$SEED" --no-plots \
    --out "$SCRATCH/single" >"$SCRATCH/logs/single.log" 2>&1 ||
  { tail -n 5 "$SCRATCH/logs/single.log" >&2; fail "the single-host run (scripts/run) failed"; }
for f in table2.json table2_detail.json table2.txt stats_time.csv stats_range.csv realizations.csv \
         ensemble_state.json scenario.json; do
  [[ -f $logger_out/$f ]] || fail "the two-host run wrote no $f (in $logger_out)"
  cmp "$logger_out/$f" "$SCRATCH/single/$f" >&2 || fail "$f differs between the two-host and the single-host run"
done
OK=1
awk -v a="$T_START" -v b="$(date +%s.%N)" -v n="$N" -v s="$SEED" 'BEGIN {
  printf "check_multihost: OK: %d realizations, seed %d, statistics byte-identical to scripts/run (test: %.1f s)\n", n, s, b - a }'

# Sourced by the shell checks that ctest runs as `check_X.sh SOURCE_DIR BUILD_DIR` over LCM
# (check_spy.sh, check_foreign_run.sh): SRC and RNAV_BUILD as absolute paths, a scratch folder
# T removed on exit, fail MESSAGE (stops the check), and in_private_net.
set -u
SRC=$(cd "$1" && pwd)
export RNAV_BUILD=$(cd "$2" && pwd)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# in_private_net SCRIPT ARG...: bash -c SCRIPT ARG... (so $0 is the first ARG) in a private
# network namespace (unshare -n: no traffic leaves the machine) whose loopback is up and carries
# multicast; SCRIPT's exit status. Fails the check if the namespace cannot be set up (exit 9).
in_private_net() {
  local script=$1 rc
  shift
  unshare -n bash -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo || exit 9
'"$script" "$@"
  rc=$?
  ((rc != 9)) || fail "cannot set up the private network namespace (needs root: unshare -n, ip)"
  return $rc
}

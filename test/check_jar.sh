#!/usr/bin/env bash
# Every lcmtypes/*.lcm must have its class in the jar that scripts/spy gives lcm-spy.
set -euo pipefail
dir=$1 jar=$2
[[ -f $jar ]] || { echo "missing jar $jar"; exit 1; }
listing=$(/usr/bin/python3 -m zipfile -l "$jar")
n=0
for f in "$dir"/*.lcm; do
  t=$(basename "$f" .lcm)
  grep -q "rnav/$t.class" <<<"$listing" || { echo "jar lacks rnav/$t.class"; exit 1; }
  n=$((n + 1))
done
echo "all $n message types are in the jar"

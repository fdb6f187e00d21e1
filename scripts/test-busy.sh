#!/usr/bin/env bash
# Runs scripts/test.sh with CPU hogs beside it (default 1: load about 3 on two cores) and
# records the load average every 30 s; prints the outcome and the wall time.
set -uo pipefail
cd "$(dirname "$0")/.."
hogs="${1:-1}"
log="${BUSY_LOG:-target/test-busy.log}"
mkdir -p "$(dirname "$log")"
pids=()
for _ in $(seq "$hogs"); do sh -c 'while :; do :; done' & pids+=($!); done
( while :; do printf '%s %s\n' "$(date +%T)" "$(cut -d' ' -f1-3 /proc/loadavg)"; sleep 30; done ) > "$log.load" & sampler=$!
trap 'kill "${pids[@]}" "$sampler" 2>/dev/null || true' EXIT
start=$(date +%s)
scripts/test.sh > "$log" 2>&1
rc=$?
end=$(date +%s)
loads=$(awk '{print $2}' "$log.load" | sort -n)
printf 'test.sh exit %s after %s s beside %s hog(s); 1-min load: min %s, median %s, max %s\n' \
  "$rc" "$((end - start))" "$hogs" "$(echo "$loads" | head -1)" "$(echo "$loads" | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')" "$(echo "$loads" | tail -1)"
exit "$rc"

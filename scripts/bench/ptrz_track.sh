#!/usr/bin/env bash
# PTRZ tracking benchmark: N (default 3) runs of `make demo SCENARIO=ptrz` (3 cameras, the ball on
# its figure eight, 60 s of simulated time, the renderer drawing every camera) in a row.
# Per run: the demo's RESULT line (max and mean error, estimates per simulated s, share of the
# image times with an estimate, centring) and its wall time; the real-time factor the simulator
# kept while the cameras rendered (the demo runs at real_time_factor 1: the renderer draws in
# wall time, so 1.00 means it kept up). Acceptance: every run SUCCESS. Results under out/bench/ptrz/.
#   bash scripts/bench/ptrz_track.sh [RUNS] [CAMERAS]
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
# shellcheck disable=SC1091
set +u; source "$root/scripts/env.sh"; set -u
runs="${1:-3}"; cameras="${2:-3}"
dir="$root/out/bench/ptrz"
mkdir -p "$dir"
summary="$dir/summary.txt"
echo "ptrz tracking, $cameras camera(s), $(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git -C "$root" rev-parse --short HEAD), load $(cut -d' ' -f1-3 /proc/loadavg)" > "$summary"
ok=0
for run in $(seq 1 "$runs"); do
  start=$(date +%s)
  "$root/src/ptrz_camera/scripts/ptrz_demo" --out "$dir/run$run" --cameras "$cameras" > "$dir/run$run.out" 2>&1
  rc=$?
  wall=$(( $(date +%s) - start ))
  result=$(grep -h '^RESULT' "$dir/run$run.out" | tail -1)
  [ -n "$result" ] || result="RESULT ptrz: FAILURE -- no result line (exit $rc; see $dir/run$run.out)"
  line="run $run: $result [wall incl. start-up ${wall} s; load $(cut -d' ' -f1 /proc/loadavg)]"
  echo "$line" | tee -a "$summary"
  if [ "$rc" -eq 0 ] && [[ "$result" == *SUCCESS* ]]; then ok=$((ok + 1)); fi
done
echo "ptrz tracking: $ok/$runs succeeded" | tee -a "$summary"
[ "$ok" -eq "$runs" ]

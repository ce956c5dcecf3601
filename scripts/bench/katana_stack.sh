#!/usr/bin/env bash
# Katana can-stack benchmark: N (default 10) runs of the pick-and-stack with both cans moved by a
# seeded random offset in +-JITTER (default 0.01 m) in x and y; the cans are found with the laser.
# Success = the top can stands 5 s after the release (tilt < 10 deg, centres within 1 cm).
# Acceptance: >= 9 of 10. Per-run results and a summary under out/bench/katana/.
#   bash scripts/bench/katana_stack.sh [-j N] [RUNS] [JITTER]
# -j N runs N seeds side by side (each katana_demo starts its own ROS master on a free port; the
# outcome runs on simulated time, only the wall times grow).
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
# shellcheck disable=SC1091
set +u; source "$root/scripts/env.sh"; set -u
jobs=1
if [ "${1:-}" = "-j" ]; then jobs="${2:-1}"; shift 2; fi
runs="${1:-10}"; jitter="${2:-0.01}"
dir="$root/out/bench/katana"
mkdir -p "$dir"
summary="$dir/summary.txt"
: > "$summary"

one() {  # one seed; prints its summary line
  local seed=$1 start wall line
  start=$(date +%s)
  "$root/src/katana_sim/scripts/katana_demo" --out "$dir/seed$seed" --jitter "$jitter" --seed "$seed" \
    > "$dir/seed$seed.out" 2>&1
  wall=$(( $(date +%s) - start ))
  line="seed $seed: $(grep -h '^RESULT' "$dir/seed$seed.out" | head -1) [wall ${wall} s] $(grep -h 'jitter (seed' "$dir/seed$seed.out" | sed 's/^\[katana\] //')"
  echo "$line" > "$dir/seed$seed.line"
  echo "$line"
}

running=0
for seed in $(seq 1 "$runs"); do
  one "$seed" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
done
wait
ok=0
for seed in $(seq 1 "$runs"); do
  cat "$dir/seed$seed.line" >> "$summary" 2>/dev/null
  if grep -q '^success: true' "$dir/seed$seed/katana_result.yaml" 2>/dev/null; then ok=$((ok + 1)); fi
done
echo "katana stack: $ok/$runs stood (jitter +-$jitter m)" | tee -a "$summary"
[ "$ok" -ge $(( runs * 9 / 10 )) ]

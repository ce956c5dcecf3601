#!/usr/bin/env bash
# Katana can-stack benchmark: N (default 10) runs of the pick-and-stack with both cans moved by a
# seeded random offset in +-JITTER (default 0.01 m) in x and y; the cans are found with the laser.
# Success = the top can stands 5 s after the release (tilt < 10 deg, centres within 1 cm).
# Acceptance: >= 9 of 10. Per-run results and a summary under out/bench/katana/.
#   bash scripts/bench/katana_stack.sh [RUNS] [JITTER]
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
# shellcheck disable=SC1091
set +u; source "$root/scripts/env.sh"; set -u
runs="${1:-10}"; jitter="${2:-0.01}"
dir="$root/out/bench/katana"
mkdir -p "$dir"
summary="$dir/summary.txt"
: > "$summary"
ok=0
for seed in $(seq 1 "$runs"); do
  start=$(date +%s)
  "$root/src/katana_sim/scripts/katana_demo" --out "$dir/seed$seed" --jitter "$jitter" --seed "$seed" \
    > "$dir/seed$seed.out" 2>&1
  wall=$(( $(date +%s) - start ))
  res="$dir/seed$seed/katana_result.yaml"
  if grep -q '^success: true' "$res" 2>/dev/null; then ok=$((ok + 1)); fi
  line="seed $seed: $(grep -h '^RESULT' "$dir/seed$seed.out" | head -1) [wall ${wall} s] $(grep -h 'jitter (seed' "$dir/seed$seed.out" | sed 's/^\[katana\] //')"
  echo "$line" | tee -a "$summary"
done
echo "katana stack: $ok/$runs stood (jitter +-$jitter m)" | tee -a "$summary"
[ "$ok" -ge $(( runs * 9 / 10 )) ]

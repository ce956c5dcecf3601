#!/usr/bin/env bash
# Katana can-stack benchmark: N (default 10) runs of the pick-and-stack with both cans moved by a
# seeded random offset in +-JITTER (default 0.01 m) in x and y; the cans are found with the laser.
# Success = the top can stands 5 s after the release (tilt < 10 deg, centres within 1 cm).
# Acceptance: >= 9 of 10. The runs are the sweep src/modrob_sweep/sweeps/katana_seeds.yaml on a
# local Ray (docs/sweeps.md): trials.csv, summary.md and plots under out/bench/katana/.
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
exec rosrun modrob_sweep sweep katana_seeds.yaml --runs "$runs" --workers "$jobs" --set jitter="$jitter" \
  --out "$root/out/bench/katana" --need $(( (runs * 9 + 9) / 10 ))

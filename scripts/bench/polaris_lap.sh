#!/usr/bin/env bash
# Polaris lap benchmark: one lap of the parking lot (pure pursuit + Ackermann), then 10 seeded
# runs with a street cone on the lap that must be detected in the (analytic HDL-32E) point cloud
# and stopped before. In-process simulator (physics core + the simulator's ros_control hardware).
# The seeded runs are the sweep src/modrob_sweep/sweeps/polaris_cones.yaml on a local Ray (J side by side).
# Writes docs/images/polaris/lap_paths.png and lap_bench.md; the sweep's trials go to out/bench/polaris_cones/. Usage: [J=2] bash scripts/bench/polaris_lap.sh [runs]
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
set +u
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
set -u
exec python3 -m polaris_description.lap_bench --out "${OUT:-$root/docs/images/polaris}" --runs "${1:-10}" --workers "${J:-1}" \
    --sweep-out "$root/out/bench/polaris_cones"

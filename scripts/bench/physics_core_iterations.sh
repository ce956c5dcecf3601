#!/usr/bin/env bash
# Our physics core and PyBullet at equal forced solver iterations (physics_core_iterations.py), in
# the benchmarks' venv that run.sh makes (scripts/bench/.venv-bench with PyBullet).
#   bash scripts/bench/physics_core_iterations.sh [--steps N] [--repeat R] [--iters 5,10,20,50]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="$here/.venv-bench"
# shellcheck disable=SC1091
set +u
source "$root/scripts/env.sh"
set -u
if [ ! -x "$venv/bin/python" ]; then
  echo "[bench] $venv is missing: run 'bash scripts/bench/run.sh --only physics_core --no-write' once" >&2
  exit 2
fi
exec "$venv/bin/python" "$here/physics_core_iterations.py" "$@"

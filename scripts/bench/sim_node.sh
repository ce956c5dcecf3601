#!/usr/bin/env bash
# Simulator node benchmark: the whole /gazebo node (headless, real_time_factor 0, 1 ms steps) on
# the physics-core scene, with PyBullet on the same URDF files in the same run.
#   bash scripts/bench/sim_node.sh [--seconds S] [--repeat N] [--no-write]
# Reuses scripts/bench/.venv-bench (made by physics_core.sh: Debian's Python with
# --system-site-packages + the pinned PyBullet); makes it the same way if it is missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="$here/.venv-bench"
# shellcheck disable=SC1091
set +u
source "$root/scripts/env.sh"
set -u
if [ ! -x "$venv/bin/python" ]; then
  echo "[bench] creating $venv (as physics_core.sh does)"
  /usr/bin/python3 -m venv --system-site-packages "$venv"
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$here/requirements-bench.txt"
fi
exec "$venv/bin/python" "$here/sim_node.py" "$@"

#!/usr/bin/env bash
# Physics core benchmark: our ODE core vs PyBullet on the same URDF scene, in one run.
#   bash scripts/bench/physics_core.sh [--steps N] [--no-write]
# Makes scripts/bench/.venv-bench once (Debian's Python, --system-site-packages so that ODE,
# numpy and the workspace are visible) with the pinned PyBullet, then runs physics_core.py, which
# prints the figures and writes the "Physics core" section of docs/benchmarks.md.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="$here/.venv-bench"
req="$here/requirements-bench.txt"
stamp="$venv/.requirements.sha256"
# shellcheck disable=SC1091
set +u
source "$root/scripts/env.sh"
set -u
if [ ! -x "$venv/bin/python" ]; then
  echo "[bench] creating $venv"
  /usr/bin/python3 -m venv --system-site-packages "$venv"
fi
want="$(sha256sum "$req" | cut -d' ' -f1)"
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]; then
  echo "[bench] installing $(grep -v '^#' "$req" | xargs) (a source build of PyBullet takes a few minutes)"
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$req"
  echo "$want" > "$stamp"
fi
exec "$venv/bin/python" "$here/physics_core.py" "$@"

#!/usr/bin/env bash
# `make bench` / `make bench FULL=1`: scripts/bench/run.py in the benchmark's own venv.
#   bash scripts/bench/run.sh [--full] [-j N] [--repeat R] [--only a,b] [--no-write]
# Makes scripts/bench/.venv-bench once (Debian's Python, --system-site-packages so that ODE, numpy,
# ROS and the workspace are visible; a .pth adds the workspace's .venv for urdfdom-py and xacro)
# with the pinned peers of requirements-bench.txt (PyBullet, MuJoCo), re-installed when that
# file changes. MuJoCo failing to install is not fatal: its rows are left out, and say so.
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
site="$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
ws_site="$(ls -d "$root"/.venv/lib/python3*/site-packages 2>/dev/null | head -1 || true)"
[ -z "$ws_site" ] || echo "$ws_site" > "$site/modrob_workspace.pth"
want="$(sha256sum "$req" | cut -d' ' -f1)"
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]; then
  echo "[bench] installing $(grep -v '^#' "$req" | xargs)"
  while read -r pkg; do
    case "$pkg" in ''|'#'*) continue;; esac
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check "$pkg" \
      || echo "[bench] WARNING: $pkg did not install; its rows are left out of the tables"
  done < "$req"
  echo "$want" > "$stamp"
fi
exec "$venv/bin/python" "$here/run.py" "$@"

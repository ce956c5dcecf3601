#!/usr/bin/env bash
# Sensors benchmark: ray casting (ODE from C, Embree via embreex when installed, numpy) and the
# real-time factor with each lidar/laser on and off, in one run; writes the "Sensors" section of
# docs/benchmarks.md.   bash scripts/bench/sensors.sh [--seconds 3] [--no-doc] [--embree]
# --embree makes scripts/bench/.venv-bench-sensors once (Debian's Python, --system-site-packages)
# with the pinned embreex of requirements-bench-sensors.txt, to measure Embree in the same run.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
set +u
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
set -u
py=python3
args=()
for a in "$@"; do
  if [ "$a" = "--embree" ]; then
    venv="$here/.venv-bench-sensors"
    if [ ! -x "$venv/bin/python" ]; then
      /usr/bin/python3 -m venv --system-site-packages "$venv"
      "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$here/requirements-bench-sensors.txt"
    fi
    py="$venv/bin/python"
  else
    args+=("$a")
  fi
done
exec "$py" "$here/sensors.py" "${args[@]}"

#!/usr/bin/env bash
# catkin_make the workspace with the venv's Python (Debian's /usr/bin/python3 plus the pinned PyPI
# extras; trap 1 of docs/development.md): catkin writes it into the shebang of every devel-space
# relay script, so rosrun/roslaunch/rostest run nodes where xacro and urdf_parser_py import.
# Serialised by a lock so that two builds started at once (two terminals, parallel test runs) cannot collide.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
export PATH="$root/.venv/bin:/usr/bin:$PATH"
exec 9>"$root/.build.lock"
flock 9
echo "[build] catkin_make in $root"
log="$root/build/catkin_make.log"
mkdir -p "$root/build"
if ! catkin_make -DPYTHON_EXECUTABLE="$root/.venv/bin/python3" -DCMAKE_BUILD_TYPE=Release "$@" > "$log" 2>&1; then
  tail -n 60 "$log" >&2
  echo "[build] catkin_make FAILED; full log: $log" >&2
  exit 1
fi
grep -E '^\[ *[0-9]+%\] Built target|warning' "$log" | tail -n 3 || true
echo "[build] ok"

#!/usr/bin/env bash
# make lint: catkin_lint on every package, flake8 on all Python (config in .flake8).
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
export PATH="$root/.venv/bin:/usr/bin:$PATH"
rc=0
echo "[lint] catkin_lint src/"
catkin_lint -W2 --strict --offline src || rc=1
echo "[lint] flake8"
mapfile -t py < <(git ls-files '*.py'; git ls-files 'src/*/scripts/*' 'src/*/nodes/*' 'src/*/test/nodes/*' | \
  while read -r f; do head -n1 "$f" 2>/dev/null | grep -q python && echo "$f"; done)
if [ ${#py[@]} -gt 0 ]; then
  python3 -m flake8 "${py[@]}" || rc=1
fi
[ $rc -eq 0 ] && echo "[lint] clean" || echo "[lint] problems found" >&2
exit $rc

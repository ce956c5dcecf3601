#!/usr/bin/env bash
# Camera renderer benchmark (frames per second per stream, simulator real-time factor with and
# without streams). Figures go to docs/benchmarks.md with --write docs/benchmarks.md.
#   bash scripts/bench/render.sh [--seconds S] [--rate FPS] [--write FILE]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
set +u
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
set -u
exec python3 "$here/render.py" "$@"

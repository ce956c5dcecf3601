#!/usr/bin/env bash
# Memory of the /gazebo node over spawn/delete cycles (see spawn_delete_memory.py --help).
#   bash scripts/bench/spawn_delete_memory.sh [--cycles N] [--every K] [--compare OTHER_CHECKOUT] [--no-write]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
set +u
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
set -u
exec python3 "$here/spawn_delete_memory.py" "$@"

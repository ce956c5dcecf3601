#!/usr/bin/env bash
# Bulbs and Slides benchmark: 20 jittered one-robot pick-and-place runs (>= 19 must succeed).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
# shellcheck disable=SC1091
set +u
source "$root/scripts/env.sh"
set -u
exec python3 "$root/scripts/bench/bulbs_and_slides.py" "$@"

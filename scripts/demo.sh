#!/usr/bin/env bash
# make demo [SCENARIO=one_robot|two_robots|ptrz|katana|polaris]
# Runs a scenario headless. A scenario that does not exist yet says so and fails: never a fake result.
#   scripts/demo.sh SCENARIO [runner arguments...]   (later arguments win: --out DIR, --seed N ...;
#   the sweeps of modrob_sweep run a demo this way, one --out per trial)
set -euo pipefail
scenario="${1:-one_robot}"
[ $# -gt 0 ] && shift
root="${MODROB_ROOT:?source scripts/env.sh first}"
mkdir -p "$root/out"
case "$scenario" in
  one_robot|two_robots)
    runner="$root/src/modrob_motion/scripts/bulbs_and_slides_demo"
    ;;
  katana)
    runner="$root/src/katana_sim/scripts/katana_demo"
    ;;
  polaris)
    runner="$root/src/polaris_description/scripts/polaris_demo"
    ;;
  ptrz)
    runner="$root/src/ptrz_camera/scripts/ptrz_demo"
    ;;
  *)
    echo "make demo: unknown SCENARIO '$scenario'; choose one of one_robot, two_robots, ptrz, katana, polaris" >&2
    exit 2
    ;;
esac
if [ -z "$runner" ] || [ ! -x "$runner" ]; then
  echo "make demo: the '$scenario' scenario is not implemented yet in this workspace." >&2
  echo "           Nothing was run. See README.md for what works today." >&2
  exit 3
fi
exec "$runner" --scenario "$scenario" --out "$root/out" "$@"

"""Command line of create_urdf_and_gazebo (argument parsing and exit codes; the work is in build).

Exit codes: 0 = files written; 2 = input refused (reason on stderr, nothing written).
"""
import argparse
import sys

from modrob_build.build import GAIN_SOURCES, RobotSpec, build_robot_set, write_outputs
from modrob_build.errors import BuildError
from modrob_build.gripper import DEFAULT_GRIP_FORCE
from modrob_build.module_database import load_database

EXIT_REFUSED = 2


def parse_base(text):
    parts = [p for p in text.replace(",", " ").split()]
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise BuildError("--base %r: expected X,Y,Z or X,Y,Z,YAW (numbers)" % text)
    if len(values) not in (3, 4):
        raise BuildError("--base %r: expected X,Y,Z or X,Y,Z,YAW, got %d numbers" % (text, len(values)))
    return values


def make_parser(prog="create_urdf_and_gazebo"):
    p = argparse.ArgumentParser(
        prog=prog, description="Module orders -> Gazebo-ready URDF, controller YAML and launch files "
        "for one or several modular robots.",
        epilog="example: %s --order 59,3,55,63,57,5 --base 0,0,1.02 --order 59,3,55,63,57,5 "
        "--base 0.5,0,1.02 --gripper --safety-distance 0.8 --out /tmp/robots" % prog)
    p.add_argument("--order", action="append", required=True,
                   help="module IDs of one robot, base first (repeat for more robots)")
    p.add_argument("--base", action="append", default=[],
                   help="X,Y,Z[,YAW] of a robot's base in the world (one per --order, or none)")
    p.add_argument("--gripper", action="store_true", help="attach the two-finger gripper")
    p.add_argument("--grip-force", type=float, default=DEFAULT_GRIP_FORCE,
                   help="finger effort limit in N (default %(default)s; tested stable up to 7)")
    p.add_argument("--safety-distance", type=float, default=0.0,
                   help="minimum x-y distance between bases in m; 0 (default) = off")
    p.add_argument("--database", default=None, help="module database (default: modrob_description's "
                   "config/Modules.csv)")
    p.add_argument("--gains", choices=GAIN_SOURCES, default="tuned",
                   help="PID gains: 'tuned' (default) takes them from the auto-tuner's table for the "
                   "orders it holds (others fall back to 'computed', with a message); 'computed' "
                   "derives them from the link inertias")
    p.add_argument("--gains-table", default=None,
                   help="the tuned gains table (default: modrob_build's config/tuned_gains.yaml)")
    p.add_argument("--out", required=True, help="output folder")
    return p


def run(args, out=sys.stdout):
    """Build and write; raises BuildError on refused input."""
    if args.base and len(args.base) != len(args.order):
        raise BuildError("%d --base for %d --order: give one --base per --order, or none"
                         % (len(args.base), len(args.order)))
    bases = [parse_base(b) for b in args.base] or [None] * len(args.order)
    specs = [RobotSpec(order, base) for order, base in zip(args.order, bases)]
    db = load_database(args.database)
    result = build_robot_set(specs, gripper=args.gripper, grip_force=args.grip_force,
                             safety_distance=args.safety_distance, db=db, out_dir=args.out,
                             gains=args.gains, gains_table=args.gains_table)
    for msg in result.messages:
        print("[create_urdf_and_gazebo] %s" % msg, file=out)
    for path in write_outputs(result, args.out):
        print("[create_urdf_and_gazebo] wrote %s" % path, file=out)
    return result


def main(argv=None, prog="create_urdf_and_gazebo"):
    args = make_parser(prog).parse_args(argv)
    try:
        run(args)
    except BuildError as e:
        print("%s: refused: %s" % (prog, e), file=sys.stderr)
        print("%s: nothing was written" % prog, file=sys.stderr)
        return EXIT_REFUSED
    return 0

"""Command line of scripts/ptrz_description (pure: no rospy)."""
import argparse
import sys

from ptrz_camera import description
from ptrz_camera.errors import ConfigError


def main(argv=None):
    parser = argparse.ArgumentParser(description="URDF of one PTRZ camera on stdout")
    parser.add_argument("--ns", default="ptrz", help="robot namespace (default ptrz)")
    parser.add_argument("--prefix", default=None,
                        help="link name prefix (default: '<ns>_' with --poses, else '')")
    parser.add_argument("--poses", default="",
                        help="YAML of poles {ns: {x, y, yaw}}; the entry named --ns is used")
    parser.add_argument("--list", type=int, default=None, metavar="N",
                        help="print the first N namespaces of --poses instead (fails if it has fewer)")
    parser.add_argument("xacro_args", nargs="*", help="more xacro arguments name:=value (fov, width, ...)")
    args = parser.parse_args(argv)
    extra = {}
    for item in args.xacro_args:
        if ":=" not in item:
            sys.stderr.write("ptrz_description: '%s' is not name:=value\n" % item)
            return 2
        k, v = item.split(":=", 1)
        extra[k] = v
    try:
        if args.list is not None:
            if not args.poses:
                raise ConfigError("--list needs --poses")
            sys.stdout.write(" ".join(description.network_names(args.list, args.poses)))
            return 0
        pose = (0.0, 0.0, 0.0)
        prefix = args.prefix if args.prefix is not None else ""
        if args.poses:
            poses = description.load_camera_poses(args.poses)
            if args.ns not in poses:
                raise ConfigError("%s has no pose for camera '%s' (it has %s): add one"
                                  % (args.poses, args.ns, ", ".join(poses)))
            pose = poses[args.ns]
            if args.prefix is None:
                prefix = args.ns + "_"
        sys.stdout.write(description.robot_description(args.ns, prefix, pose, **extra))
    except ConfigError as exc:
        sys.stderr.write("ptrz_description: %s\n" % exc)
        return 1
    return 0

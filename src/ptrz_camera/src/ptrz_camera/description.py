"""The camera's robot description: urdf/ptrz.xacro processed with ``xacro --xacro-ns`` (the seed
defines a macro named ``link``), and the poles of a camera network from config/cameras.yaml."""
import math
import os
import shutil
import subprocess

import yaml

from ptrz_camera.errors import ConfigError

PACKAGE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
XACRO_FILE = os.path.join(PACKAGE_DIR, "urdf", "ptrz.xacro")
CAMERAS_FILE = os.path.join(PACKAGE_DIR, "config", "cameras.yaml")


def load_camera_poses(path=CAMERAS_FILE):
    """``{ns: (x, y, yaw)}`` in file order from a YAML of ``ns: {x, y, yaw}``."""
    try:
        with open(path) as f:
            data = yaml.safe_load(f)
    except OSError as exc:
        raise ConfigError("camera poses file %s cannot be read: %s" % (path, exc.strerror))
    except yaml.YAMLError as exc:
        raise ConfigError("camera poses file %s is not valid YAML: %s" % (path, exc))
    if not isinstance(data, dict) or not data:
        raise ConfigError("camera poses file %s must map namespaces to {x, y, yaw}, e.g. "
                          "'ptrz1: {x: 0, y: 0, yaw: 0}'" % path)
    poses = {}
    for ns, entry in data.items():
        if not isinstance(entry, dict):
            raise ConfigError("%s: entry '%s' must be {x: .., y: .., yaw: ..}" % (path, ns))
        values = []
        for key in ("x", "y", "yaw"):
            value = entry.get(key, 0.0)
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise ConfigError("%s: %s.%s = %r is not a number" % (path, ns, key, value))
            if not math.isfinite(value):
                raise ConfigError("%s: %s.%s = %r is not finite" % (path, ns, key, value))
            values.append(value)
        unknown = set(entry) - {"x", "y", "yaw"}
        if unknown:
            raise ConfigError("%s: %s has unknown keys %s (allowed: x, y, yaw)" % (path, ns, sorted(unknown)))
        poses[str(ns)] = tuple(values)
    return poses


def network_names(count, path=CAMERAS_FILE):
    """The first ``count`` camera namespaces of the poses file (ConfigError if it has fewer)."""
    poses = load_camera_poses(path)
    names = list(poses)
    if count < 1 or count > len(names):
        raise ConfigError("cameras:=%d but %s has poses for %d camera(s) (%s): add poses or ask for fewer"
                          % (count, path, len(names), ", ".join(names)))
    return names[:count]


def xacro_command():
    exe = shutil.which("xacro")
    if exe is None:
        raise ConfigError("the xacro command is not on PATH: source scripts/env.sh (xacro 1.13 comes from "
                          "requirements.txt)")
    return exe


def robot_description(ns="ptrz", prefix="", pose=(0.0, 0.0, 0.0), xacro_file=XACRO_FILE, **args):
    """URDF text of one camera: ``ns`` (robot namespace), ``prefix`` (link names), ``pose`` of the
    pole ``(x, y, yaw)``, and further xacro arguments (fov, width, height, update_rate, ...)."""
    mappings = dict(ns=ns, prefix=prefix, x=pose[0], y=pose[1], yaw=pose[2])
    mappings.update(args)
    cmd = [xacro_command(), "--xacro-ns", xacro_file]
    cmd += ["%s:=%s" % (k, v) for k, v in sorted(mappings.items())]
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
    if proc.returncode != 0:
        raise ConfigError("xacro failed on %s: %s" % (xacro_file, proc.stderr.strip().splitlines()[-1:]))
    return proc.stdout

"""The table of PID gains measured by the auto-tuner (``rosrun modrob_motion tune_pid --all``), which
the generated robots take as their default gains.

    robots:
      59,3,55,63,57,5+gripper:          # module order, "+gripper" when the gripper is attached
        joint1: {p: ..., i: ..., d: ..., i_clamp: ..., antiwindup: true,
                 method: relay+robot+sine, at: {...}, overshoot: ..., ...}   # tuner's notes

An order without an entry (or a joint missing from one) falls back to the gains computed from the
link inertias (modrob_build.gains), and the build says so with the command that tunes it. The
gripper's finger is not in the table: its gains follow from the grip force (a force-limited clamp).
"""
import math
import os

import yaml

from modrob_build.errors import BuildError

PID_KEYS = ("p", "i", "d", "i_clamp")


def default_table_path():
    """config/tuned_gains.yaml of the modrob_build package (rospkg, else the source tree)."""
    try:
        import rospkg
        root = rospkg.RosPack().get_path("modrob_build")
    except Exception:  # noqa: B902 - rospkg raises its own types or is not configured
        root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    return os.path.normpath(os.path.join(root, "config", "tuned_gains.yaml"))


def order_key(order, gripper):
    """'59,3,55,63,57,5+gripper': how the table names a robot."""
    return ",".join(str(int(m)) for m in order) + ("+gripper" if gripper else "")


class TunedGains(object):
    """The parsed table: ``lookup(order, gripper) -> {joint: pid dict}`` (empty if not tuned)."""

    def __init__(self, robots, path):
        self.robots = robots
        self.path = path

    def lookup(self, order, gripper):
        entry = self.robots.get(order_key(order, gripper)) or {}
        return {joint: {k: float(v[k]) for k in PID_KEYS} for joint, v in entry.items()}

    def keys(self):
        return sorted(self.robots)


def _check_entry(path, key, joint, value):
    where = "%s: robots/%s/%s" % (path, key, joint)
    if not isinstance(value, dict):
        raise BuildError("%s is not a mapping of gains (p, i, d, i_clamp): regenerate the table with "
                         "`rosrun modrob_motion tune_pid --all`" % where)
    for k in PID_KEYS:
        v = value.get(k)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
            raise BuildError("%s: '%s' is %r, not a finite number >= 0: fix or regenerate the table"
                             % (where, k, v))


def load_tuned_gains(path=None):
    """Read and validate the table. A missing file is an empty table (every robot falls back to the
    computed gains); a malformed one raises BuildError naming the file and the entry."""
    path = path or default_table_path()
    if not os.path.exists(path):
        return TunedGains({}, path)
    try:
        with open(path) as fh:
            data = yaml.safe_load(fh) or {}
    except OSError as e:
        raise BuildError("cannot read the tuned gains table %s: %s" % (path, e.strerror))
    except yaml.YAMLError as e:
        raise BuildError("the tuned gains table %s is not valid YAML (%s): fix it or regenerate it with "
                         "`rosrun modrob_motion tune_pid --all`" % (path, str(e).replace("\n", " ")))
    robots = data.get("robots") if isinstance(data, dict) else None
    if robots is None:
        robots = {}
    if not isinstance(robots, dict):
        raise BuildError("%s: 'robots' must map module orders to joints, got %s"
                         % (path, type(robots).__name__))
    for key, joints in robots.items():
        if not isinstance(joints, dict):
            raise BuildError("%s: robots/%s must map joint names to gains" % (path, key))
        for joint, value in joints.items():
            _check_entry(path, key, joint, value)
    return TunedGains({str(k): v for k, v in robots.items()}, path)

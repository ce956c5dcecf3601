"""Module orders + base positions -> every file the simulator and RViz need (pure, no rospy).

    result = build_robot_set([RobotSpec([59, 3, 55, 63, 57, 5], (0, 0, 1.02))], gripper=True)
    result.files            # {file name: text}: modrob0.urdf, modrob0_controllers.yaml,
                            #  modrob_spawn.launch, modrob_robots.launch, modrob_robots.yaml
    result.messages         # what was adjusted (safety distance, warnings)
    write_outputs(result, "/tmp/out")

Everything is generated and validated in memory first; files are written only when all of it
succeeded (each through a temporary file and a rename), so refused input writes nothing.
"""
import os
import tempfile

import yaml

from modrob_build.controller_config import controller_names, controller_yaml
from modrob_build.errors import BuildError, LayoutError
from modrob_build.gripper import DEFAULT_GRIP_FORCE, attach_gripper, check_grip_force
from modrob_build.launch_writer import robots_launch, spawn_launch
from modrob_build.module_database import load_database
from modrob_build.order import parse_order, validate_order
from modrob_build.robot_model import base_pose_tuple, build_robot_model
from modrob_build.safety_distance import enforce_safety_distance
from modrob_build.tuned_gains import load_tuned_gains, order_key
from modrob_build.urdf_writer import default_comment, robot_element, to_text

DEFAULT_SPACING = 1.0   # metres between default bases along y
GAIN_SOURCES = ("tuned", "computed")


class RobotSpec(object):
    """One robot: module order (list or text) and base pose (x, y, z[, yaw]) or None."""

    def __init__(self, order, base=None):
        self.order = order
        self.base = base


class BuildResult(object):
    def __init__(self):
        self.files = {}        # name -> text, in write order
        self.robots = []       # RobotModel per robot
        self.messages = []
        self.manifest = None


def default_bases(count):
    return [(0.0, DEFAULT_SPACING * i, 0.0, 0.0) for i in range(count)]


def _bases(specs):
    given = [s.base is not None for s in specs]
    if not any(given):
        return default_bases(len(specs))
    if not all(given):
        missing = [i for i, g in enumerate(given) if not g]
        raise LayoutError("base positions given for some robots but not for modrob%s: give one "
                          "--base per --order, or none (defaults: x=0, y=%g*N, z=0)"
                          % (", modrob".join(str(i) for i in missing), DEFAULT_SPACING))
    return [base_pose_tuple(s.base) for s in specs]


def build_robot_set(specs, gripper=False, grip_force=DEFAULT_GRIP_FORCE, safety_distance=0.0,
                    db=None, out_dir=None, first_index=0, gains="tuned", gains_table=None):
    """BuildResult for a list of RobotSpec, numbered modrob<first_index>, modrob<first_index+1> ...
    out_dir is where the files will live (the launch files refer to the URDF and YAML by absolute
    path); default: the current directory.

    gains: "tuned" (default: the auto-tuner's table, modrob_build.tuned_gains, for the orders it
    holds; the others fall back to "computed" with a message) or "computed" (from the inertias,
    modrob_build.gains). gains_table: the table's path (default config/tuned_gains.yaml)."""
    if gains not in GAIN_SOURCES:
        raise BuildError("gains %r: choose one of %s" % (gains, ", ".join(GAIN_SOURCES)))
    table = load_tuned_gains(gains_table) if gains == "tuned" else None
    if not specs:
        raise BuildError("no robot: give at least one module order (e.g. --order 59,3,55,63,57,5)")
    db = db or load_database()
    out_dir = os.path.abspath(out_dir or os.getcwd())
    result = BuildResult()
    orders = []
    for n, spec in enumerate(specs):
        try:
            order = parse_order(spec.order)
            modules = validate_order(order, db)
        except BuildError as e:
            raise type(e)("modrob%d: %s" % (first_index + n, e))
        orders.append((order, modules))
    if gripper:
        grip_force, warning = check_grip_force(grip_force)
        if warning:
            result.messages.append(warning)
    bases, moved = enforce_safety_distance(
        _bases(specs), safety_distance, names=["modrob%d" % (first_index + n) for n in range(len(specs))])
    result.messages.extend(moved)
    spawn_entries, manifest = [], []
    for n, ((order, modules), base) in enumerate(zip(orders, bases)):
        robot = build_robot_model(modules, order, index=first_index + n, base=base)
        result.robots.append(robot)
        root = robot_element(robot, default_comment(robot))
        if gripper:
            urdf = attach_gripper(root, robot.prefix, robot.ee_link, grip_force)
        else:
            urdf = to_text(root)
        urdf_name, yaml_name = "%s.urdf" % robot.name, "%s_controllers.yaml" % robot.name
        result.files[urdf_name] = urdf
        tuned = table.lookup(order, gripper) if table is not None else {}
        sources = {}
        yaml_text = controller_yaml(robot, gripper, grip_force, tuned=tuned, sources=sources)
        header = ("ros_control configuration of %s (module order %s), generated by modrob_build.\n%s"
                  % (robot.name, order, _gains_note(sources, table, order, gripper)))
        result.files[yaml_name] = "".join("# %s\n" % line for line in header.splitlines()) + yaml_text
        computed = sorted(j for j, s in sources.items() if s == "computed")
        if table is not None and computed:
            result.messages.append(
                "%s: no tuned gains for %s of module order %s in %s; using gains computed from the "
                "inertias. Tune them: rosrun modrob_motion tune_pid --order %s%s --all --table %s"
                % (robot.name, ", ".join(computed), order_key(order, gripper), table.path,
                   order_key(order, False), " --gripper" if gripper else "", table.path))
        controllers = controller_names(robot, gripper)
        spawn_entries.append((robot.name, os.path.join(out_dir, urdf_name),
                              os.path.join(out_dir, yaml_name), controllers))
        manifest.append({"name": robot.name, "namespace": robot.namespace, "order": list(order),
                         "base": [round(v, 6) for v in robot.base_pose],
                         "urdf": urdf_name, "controllers_yaml": yaml_name,
                         "joints": [j.name for j in robot.actuated_joints],
                         "controllers": controllers, "gains": dict(sorted(sources.items())),
                         "ee_link": robot.ee_link,
                         "tool_link": robot.prefix + ("gripper_tcp" if gripper else "ee_link")})
    comment = (" generated by modrob_build (create_urdf_and_gazebo) for %d robot(s); regenerate "
               "rather than edit. " % len(specs))
    result.files["modrob_spawn.launch"] = spawn_launch(spawn_entries, comment)
    result.files["modrob_robots.launch"] = robots_launch(os.path.join(out_dir, "modrob_spawn.launch"),
                                                         comment)
    result.manifest = {"robots": manifest, "gripper": bool(gripper),
                       "grip_force": float(grip_force) if gripper else None,
                       "safety_distance": float(safety_distance), "database": db.path,
                       "messages": list(result.messages)}
    result.files["modrob_robots.yaml"] = yaml.safe_dump(result.manifest, sort_keys=False)
    return result


def _gains_note(sources, table, order, gripper):
    tuned = [j for j in sorted(sources) if sources[j] == "tuned"]
    computed = [j for j in sorted(sources) if sources[j] == "computed"]
    lines = []
    if tuned:
        lines.append("Gains of %s: tuned by `rosrun modrob_motion tune_pid --all` (table %s, entry %s)."
                     % (", ".join(tuned), table.path, order_key(order, gripper)))
    if computed:
        lines.append("Gains of %s: computed from the link inertias and effort limits (docs/modules.md); "
                     "tune them with `rosrun modrob_motion tune_pid --all`." % ", ".join(computed))
    if gripper:
        lines.append("Gripper finger gains: from the grip force (the finger saturates at it).")
    return "\n".join(lines)


def write_outputs(result, out_dir):
    """Write every file of a BuildResult into out_dir (created if needed). Returns the paths."""
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as e:
        raise BuildError("cannot create the output folder %s: %s" % (out_dir, e.strerror))
    paths = []
    for name, text in result.files.items():
        path = os.path.join(out_dir, name)
        try:
            fd, tmp = tempfile.mkstemp(prefix="." + name, dir=out_dir)
            with os.fdopen(fd, "w") as f:
                f.write(text)
            os.chmod(tmp, 0o644)
            os.replace(tmp, path)
        except OSError as e:
            raise BuildError("cannot write %s: %s" % (path, e.strerror))
        paths.append(path)
    return paths

"""Which position controller drives which joint, read from ros_control's controller parameters.

ros_control keeps a controller's configuration under ``<robot namespace>/<controller name>``
with ``type`` and ``joint`` keys. Reading it (rather than assuming a naming pattern) keeps
``motion_publisher`` right for any robot the module build generates. Pure: the ROS layer passes
the parameter tree it got from ``rosparam``.
"""
import re

from modrob_motion.errors import MotionError

POSITION_CONTROLLER_TYPES = (
    "effort_controllers/JointPositionController",
    "position_controllers/JointPositionController",
)


def natural_key(text):
    """Sort key that puts joint2 before joint10."""
    return [int(p) if p.isdigit() else p for p in re.split(r"(\d+)", text)]


def position_controllers(params, namespace="/"):
    """``{joint_name: controller_name}`` for every single-joint position controller in ``params``
    (the dict under a robot's namespace). Raises MotionError when there is none."""
    found = {}
    if isinstance(params, dict):
        for name, cfg in params.items():
            if not isinstance(cfg, dict):
                continue
            if cfg.get("type") in POSITION_CONTROLLER_TYPES and isinstance(cfg.get("joint"), str):
                joint = cfg["joint"]
                if joint in found:
                    raise MotionError("joint '%s' has two position controllers under %s: '%s' and '%s'"
                                      % (joint, namespace, found[joint], name))
                found[joint] = name
    if not found:
        raise MotionError(
            "no position controllers (%s) found under %s: load the robot's controller YAML "
            "(for example modrob0.yaml from create_urdf_and_gazebo) into that namespace"
            % (" or ".join(POSITION_CONTROLLER_TYPES), namespace))
    return found


def command_topic(namespace, controller_name):
    """``/modrob0`` + ``joint1_position_controller`` -> ``/modrob0/joint1_position_controller/command``."""
    ns = "/" + namespace.strip("/") if namespace.strip("/") else ""
    return "%s/%s/command" % (ns, controller_name)

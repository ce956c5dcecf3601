"""Force/torque sensing on a joint: gazebo_ros_ft_sensor (a model plugin naming ``jointName``) and
Gazebo 11's ``<sensor type="force_torque">`` (on a joint; its ``<force_torque>`` block).

Both read what the joint transmits in the last physics step (the physics core's
``Joint.transmitted_wrench``: ODE's joint feedback plus the effort applied to the joint), as
Gazebo's ``Joint::GetForceTorque`` gives it: the torque about the joint origin, and

- ``<frame>``: ``child`` (default: the child link's frame), ``parent`` (the parent link's, the world
  for a joint to ``world``) or ``sensor`` (the sensor's ``<pose>`` on the joint: the vectors are
  only rotated, as Gazebo does, not moved to the sensor origin);
- ``<measure_direction>``: ``child_to_parent`` (default: the wrench the child exerts on the parent;
  a mass hanging below the joint reads its weight downwards) or ``parent_to_child`` (the opposite).

gazebo_ros_ft_sensor always reports child frame, child_to_parent.
"""
from modrob_sim.physics.transforms import IDENTITY_POSE, pose_inv, pose_mul, quat_conj, quat_mul, quat_rotate

from .errors import SensorConfigError

FRAMES = ("child", "parent", "sensor")
DIRECTIONS = ("child_to_parent", "parent_to_child")
ZERO = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))


class JointWrench(object):
    """The wrench a joint transmits, in one of Gazebo's frames and directions.

    ``sensor_pose``: the sensor's ``<pose>`` in the joint frame (only for ``frame`` sensor)."""

    def __init__(self, joint, where, frame="child", direction="child_to_parent", sensor_pose=IDENTITY_POSE):
        if frame not in FRAMES:
            raise SensorConfigError("%s: <force_torque><frame> '%s' is not one of %s"
                                    % (where, frame, ", ".join(FRAMES)))
        if direction not in DIRECTIONS:
            raise SensorConfigError("%s: <force_torque><measure_direction> '%s' is not one of %s"
                                    % (where, direction, ", ".join(DIRECTIONS)))
        if not joint.measure_wrench():
            raise SensorConfigError(
                "%s: joint '%s' is %s: the simulator welds the links of a fixed joint into one body "
                "(as Gazebo lumps them), so nothing carries a force there to measure; put the sensor "
                "on a revolute or prismatic joint" % (where, joint.name, joint.type))
        self.joint = joint
        self.frame = frame
        self.sign = -1.0 if direction == "child_to_parent" else 1.0
        model = joint.model
        self.child = model.links[joint.child]
        self.parent = model.links.get(joint.parent)     # None for 'world'
        # the sensor's rotation in the child link frame: child link -> joint frame -> sensor
        joint_in_child = pose_inv(joint.child_offset)
        self.sensor_in_child = pose_mul(joint_in_child, sensor_pose)[1]

    def read(self):
        """``(force, torque)`` of the last step in the chosen frame and direction (zero before
        the first step)."""
        w = self.joint.transmitted_wrench()
        if w is None:
            return ZERO
        f, t = w
        if self.frame == "parent":
            q = self.parent.pose[1] if self.parent is not None else (0.0, 0.0, 0.0, 1.0)
        elif self.frame == "child":
            q = self.child.pose[1]
        else:
            q = quat_mul(self.child.pose[1], self.sensor_in_child)
        inv = quat_conj(q)
        s = self.sign
        fl, tl = quat_rotate(inv, f), quat_rotate(inv, t)
        return (s * fl[0], s * fl[1], s * fl[2]), (s * tl[0], s * tl[1], s * tl[2])

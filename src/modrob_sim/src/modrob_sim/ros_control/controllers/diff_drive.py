"""diff_drive_controller/DiffDriveController (ros_controllers, Noetic) on velocity joints.

``left_wheel`` / ``right_wheel``: a joint name or a list of them (every wheel of a side gets the
same command; the odometry uses the mean position of each side). ``wheel_separation`` and
``wheel_radius`` (m): when not given they are read from the model as ros_controllers reads them
from the URDF: the distance between the first left and the first right wheel joint's origins, and
the radius of the first left wheel link's collision cylinder or sphere. ``wheel_separation_multiplier``,
``wheel_radius_multiplier`` (sets both sides) or ``left_wheel_radius_multiplier`` /
``right_wheel_radius_multiplier`` (1.0) scale them. ``publish_cmd``: the limited command on
``cmd_vel_out``; ``publish_wheel_joint_controller_state``: the wheels' desired and actual state on
``wheel_joint_controller_state``. The rest is mobile_base's.

Wheel speeds: left = (v - w * s / 2) / r_left, right = (v + w * s / 2) / r_right.
"""
import math

from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.controllers.mobile_base import MobileBaseController, positive
from modrob_sim.ros_control.transmissions import VELOCITY


def wheel_names(params, key):
    """ros_controllers' getWheelNames: a string or a non-empty list of strings."""
    if not params.has(key):
        raise ControllerError("Parameter %s is missing: the wheel joint name, or a list of them "
                              "(e.g. \"%s: ['front_%s', 'rear_%s']\")" % (params.path(key), key, key, key))
    value = params.get(key)
    if isinstance(value, str) and value:
        return [value]
    if isinstance(value, list) and value and all(isinstance(v, str) and v for v in value):
        return list(value)
    raise ControllerError("Parameter %s must be a joint name or a non-empty list of joint names, got %r"
                          % (params.path(key), value))


def joint_origin_distance(a, b):
    """Distance between two joints' origins in their parent frames (the URDF's
    parent_to_joint_origin_transform positions), as ros_controllers measures wheel separation."""
    pa, pb = a.sim.origin[0], b.sim.origin[0]
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(pa, pb)))


def wheel_radius_of(res, controller, shapes=("cylinder", "sphere")):
    """The radius of the collision geometry of the link a wheel joint moves."""
    sim = res.sim
    model = getattr(sim, "model", None)
    link = model.links.get(sim.child) if model is not None else None
    if link is None:
        raise ControllerError("controller '%s': wheel_radius is not set and the link of joint '%s' is not "
                              "known: set wheel_radius" % (controller, res.name))
    if not link.collisions:
        raise ControllerError("controller '%s': wheel_radius is not set and wheel link '%s' has no "
                              "collision: add a collision %s to the link, or set wheel_radius"
                              % (controller, link.name, " or ".join(shapes)))
    geom = link.collisions[0]
    if geom.kind not in shapes:
        raise ControllerError("controller '%s': wheel_radius is not set and wheel link '%s' is NOT "
                              "modeled as a %s (its collision is a %s): set wheel_radius"
                              % (controller, link.name, " or ".join(shapes), geom.kind))
    return float(geom.size[0])


class DiffDriveController(MobileBaseController):
    TYPE = "diff_drive_controller/DiffDriveController"
    INTERFACE = VELOCITY

    def __init__(self, name, hw, params):
        super(DiffDriveController, self).__init__(name, hw, params)
        left = wheel_names(params, "left_wheel")
        right = wheel_names(params, "right_wheel")
        if len(left) != len(right):
            raise ControllerError("controller '%s': #left wheels (%d) != #right wheels (%d) (parameters %s "
                                  "and %s)" % (name, len(left), len(right), params.path("left_wheel"),
                                               params.path("right_wheel")))
        self.left = [hw.joint(j, VELOCITY, controller=name) for j in left]
        self.right = [hw.joint(j, VELOCITY, controller=name) for j in right]
        self.joint_names = left + right
        self.wheel_separation_multiplier = positive(params, "wheel_separation_multiplier", 1.0)
        if params.has("wheel_radius_multiplier"):
            m = positive(params, "wheel_radius_multiplier", 1.0)
            self.left_radius_multiplier = self.right_radius_multiplier = m
        else:
            self.left_radius_multiplier = positive(params, "left_wheel_radius_multiplier", 1.0)
            self.right_radius_multiplier = positive(params, "right_wheel_radius_multiplier", 1.0)
        if params.has("wheel_separation"):
            self.wheel_separation = positive(params, "wheel_separation", 1.0)
        else:
            self.wheel_separation = joint_origin_distance(self.left[0], self.right[0])
            if self.wheel_separation <= 0.0:
                raise ControllerError("controller '%s': joints '%s' and '%s' are at the same place, so "
                                      "the wheel separation read from the model is 0: set wheel_separation"
                                      % (name, left[0], right[0]))
        if params.has("wheel_radius"):
            self.wheel_radius = positive(params, "wheel_radius", 1.0)
        else:
            self.wheel_radius = wheel_radius_of(self.left[0], name)
        self.publish_wheel_state = params.get("publish_wheel_joint_controller_state", False, kind=bool)
        self._desired = [0.0] * len(self.joint_names)
        self._desired_pos = None
        self._desired_time = None       # the update that last integrated the desired positions
        self._last_sides = None

    # dimensions with the (live) multipliers
    @property
    def separation(self):
        return self.wheel_separation * self.wheel_separation_multiplier

    @property
    def radii(self):
        return (self.wheel_radius * self.left_radius_multiplier,
                self.wheel_radius * self.right_radius_multiplier)

    def interfaces(self):
        return [(VELOCITY, self.joint_names)]

    def _sides(self):
        """Mean wheel angle of each side (rad); None when a wheel reads NaN."""
        lp = [j.position for j in self.left]
        rp = [j.position for j in self.right]
        if any(math.isnan(p) for p in lp + rp):
            return None
        return sum(lp) / len(lp), sum(rp) / len(rp)

    def starting(self, t):
        self._last_sides = self._sides()
        self._desired_time = None       # no update while stopped: nothing to integrate for it
        super(DiffDriveController, self).starting(t)

    def measure(self):
        sides = self._sides()
        if sides is None:
            return None
        last, self._last_sides = self._last_sides, sides
        if last is None:
            return 0.0, 0.0
        rl, rr = self.radii
        dl = (sides[0] - last[0]) * rl
        dr = (sides[1] - last[1]) * rr
        return 0.5 * (dl + dr), (dr - dl) / self.separation

    def drive(self, linear, angular):
        rl, rr = self.radii
        half = angular * self.separation / 2.0
        vl = (linear - half) / rl
        vr = (linear + half) / rr
        for j in self.left:
            j.command = vl
        for j in self.right:
            j.command = vr
        self._desired = [vl] * len(self.left) + [vr] * len(self.right)

    def update(self, t, dt):
        before = self._desired
        super(DiffDriveController, self).update(t, dt)
        if not self.publish_wheel_state:
            return
        joints = self.left + self.right
        if self._desired_pos is None:
            self._desired_pos = [j.position for j in joints]
        else:
            # the updates the World made natively since the last one (nobody listened) held the
            # wheel speeds `before`: each integrates them as it would have, then this one its own
            pos = self._desired_pos
            if self._desired_time is not None:
                for _ in range(int(round((t - self._desired_time) / dt)) - 1):
                    pos = [p + v * dt for p, v in zip(pos, before)]
            self._desired_pos = [p + v * dt for p, v in zip(pos, self._desired)]
        self._desired_time = t
        acc = [(v - v0) / dt if dt > 0.0 else 0.0 for v, v0 in zip(self._desired, before)]
        self.wheel_state = dict(stamp=t, positions=list(self._desired_pos), velocities=list(self._desired),
                                accelerations=acc)

"""Path planning for the can stack (seed 001 section 4.5), pure: waypoints in katana_base_link,
joint trajectories through the grasp IK, and the check whether a stack stands.

The seed's plan: approach a detected object along the straight line from the arm's base to it
(so the open gripper does not sweep into it), lift it higher than the top of the stack, place it,
go back along the line towards the base, then to the next object. Here a plan is a list of steps:

* ``Move(name, points)``: a joint trajectory, ``points`` = [(time_from_start, [q1..q5]), ...];
* ``Grip(name, position, max_effort)``: a gripper goal.

Straight-line segments are sampled every ``step`` metres and solved with ``kinematics.grasp_ik``
(tool horizontal, pointing away from the base); free moves interpolate in joint space. Time
follows a cosine profile (zero velocity at both ends).
"""
import math

import numpy as np

from katana_sim import kinematics as kin
from katana_sim.errors import UnreachableError
from katana_sim.gripper import CLOSED_ANGLE, OPEN_ANGLE


class Can(object):
    """A standing can: centre of its base circle on the table (x, y, z of the table top) in
    katana_base_link, radius and height (m)."""
    __slots__ = ("x", "y", "z", "radius", "height")

    def __init__(self, x, y, z=0.0, radius=0.033, height=0.122):
        self.x, self.y, self.z, self.radius, self.height = float(x), float(y), float(z), radius, height

    @property
    def xy(self):
        return np.array([self.x, self.y])

    def __repr__(self):
        return "Can(%.3f, %.3f, %.3f)" % (self.x, self.y, self.z)


class Move(object):
    __slots__ = ("name", "points", "tool_path")

    def __init__(self, name, points, tool_path):
        self.name, self.points, self.tool_path = name, points, tool_path

    @property
    def duration(self):
        return self.points[-1][0]

    @property
    def target(self):
        return self.points[-1][1]


class Grip(object):
    __slots__ = ("name", "position", "max_effort")

    def __init__(self, name, position, max_effort):
        self.name, self.position, self.max_effort = name, position, max_effort


class StackPlanner(object):
    """Plans picking ``top`` and standing it on ``bottom``; parameters in SI units."""

    def __init__(self, approach=0.07, clearance=0.04, place_gap=0.004, cart_speed=0.05,
                 joint_speed=0.5, step=0.01, grip_effort=0.5, retreat=0.09, min_move_time=1.0,
                 raise_height=0.03, carry_radius=0.32):
        self.approach, self.clearance, self.place_gap = approach, clearance, place_gap
        self.cart_speed, self.joint_speed, self.step = cart_speed, joint_speed, step
        self.grip_effort, self.retreat, self.min_move_time = grip_effort, retreat, min_move_time
        self.raise_height, self.carry_radius = raise_height, carry_radius

    # -- geometry ---------------------------------------------------------------------------
    @staticmethod
    def radial(xy):
        n = np.linalg.norm(xy)
        if n < 1e-6:
            raise UnreachableError("a can on the pan axis cannot be approached along the line from the base")
        return xy / n

    def grasp_point(self, can):
        """The tool point when the can is between the pads: the can's axis at half its height."""
        return np.array([can.x, can.y, can.z + 0.5 * can.height])

    def plan(self, q_start, top, bottom):
        """Steps from ``q_start`` to pick ``top`` and stand it on ``bottom``; UnreachableError names
        the waypoint that cannot be reached."""
        steps = []
        grasp = self.grasp_point(top)
        u_top = np.append(self.radial(top.xy), 0.0)
        pre_grasp = grasp - self.approach * u_top
        carry_z = bottom.z + bottom.height + self.clearance + 0.5 * top.height
        place_z = bottom.z + bottom.height + self.place_gap + 0.5 * top.height
        u_bottom = np.append(self.radial(bottom.xy), 0.0)
        place = np.array([bottom.x, bottom.y, place_z])
        above = np.array([bottom.x, bottom.y, carry_z])
        away = place - self.retreat * u_bottom
        # after the grasp: up off the table, back along the line towards the base (where the arm
        # can lift a can higher), up above the stack, across, down onto it
        raised = grasp + np.array([0.0, 0.0, self.raise_height])
        back = np.append(self.radial(top.xy) * min(self.carry_radius, np.linalg.norm(top.xy)), raised[2])
        back_high = np.array([back[0], back[1], carry_z])
        q = list(q_start)
        steps.append(Grip("open", OPEN_ANGLE, 0.0))
        steps.append(self.free_move("to pre-grasp", q, self._ik(pre_grasp, "pre-grasp")))
        q = steps[-1].target
        steps.append(self.line("approach", q, pre_grasp, grasp))
        q = steps[-1].target
        steps.append(Grip("close", CLOSED_ANGLE, self.grip_effort))
        steps.append(self.line("lift", q, grasp, raised))
        q = steps[-1].target
        steps.append(self.line("back", q, raised, back))
        q = steps[-1].target
        steps.append(self.line("raise", q, back, back_high))
        q = steps[-1].target
        steps.append(self.free_move("carry", q, self._ik(above, "above the stack")))
        q = steps[-1].target
        steps.append(self.line("place", q, above, place))
        q = steps[-1].target
        steps.append(Grip("release", OPEN_ANGLE, 0.0))
        steps.append(self.line("retreat", q, place, away))
        q = steps[-1].target
        steps.append(self.free_move("home", q, list(kin.HOME)))
        return steps

    # -- trajectories ---------------------------------------------------------------------------
    def _ik(self, p, what):
        try:
            return kin.grasp_ik(p)
        except UnreachableError as exc:
            raise UnreachableError("%s: %s" % (what, exc))

    def line(self, name, q_start, a, b):
        """Straight tool path a -> b, IK every ``step`` m, cosine time profile at cart_speed."""
        a, b = np.asarray(a, float), np.asarray(b, float)
        length = float(np.linalg.norm(b - a))
        n = max(2, int(math.ceil(length / self.step)) + 1)
        duration = max(self.min_move_time, 1.5 * length / self.cart_speed)
        points, path = [], []
        for i in range(1, n):
            s = i / (n - 1.0)
            p = a + (b - a) * s
            q = self._ik(p, "%s (%.3f, %.3f, %.3f)" % (name, p[0], p[1], p[2]))
            points.append((duration * _time_of(s), q))
            path.append(p)
        _unwrap(q_start, points)
        return Move(name, points, [a] + path)

    def free_move(self, name, q_start, q_goal, n=12):
        dq = max(abs(g - s) for g, s in zip(q_goal, q_start))
        duration = max(self.min_move_time, 1.5 * dq / self.joint_speed)
        points, path = [], []
        for i in range(1, n + 1):
            s = i / float(n)
            w = 0.5 - 0.5 * math.cos(math.pi * s)
            q = [qs + (qg - qs) * w for qs, qg in zip(q_start, q_goal)]
            points.append((duration * s, q))
            path.append(kin.tool_position(q))
        return Move(name, points, [kin.tool_position(q_start)] + path)


def _time_of(s):
    """Inverse of the cosine profile: the time fraction at which the path fraction s is reached."""
    return math.acos(max(-1.0, min(1.0, 1.0 - 2.0 * s))) / math.pi


def _unwrap(q_start, points):
    """Keep joint 1 and 5 on the side of q_start (IK answers are in (-pi, pi])."""
    prev = list(q_start)
    for _, q in points:
        for j in (0, 4):
            while q[j] - prev[j] > math.pi:
                q[j] -= 2 * math.pi
            while q[j] - prev[j] < -math.pi:
                q[j] += 2 * math.pi
        prev = q


# ------------------------------------------------------------------------------------------------
def tilt_of(quaternion):
    """Angle (rad) between a body's z axis and the world's z axis; quaternion (x, y, z, w)."""
    x, y, z, w = quaternion
    zz = 1.0 - 2.0 * (x * x + y * y)
    return math.acos(max(-1.0, min(1.0, zz)))


class StackOutcome(object):
    __slots__ = ("success", "tilt_deg", "offset", "height_error", "text")

    def __init__(self, success, tilt_deg, offset, height_error, text):
        self.success, self.tilt_deg, self.offset = success, tilt_deg, offset
        self.height_error, self.text = height_error, text


def judge_stack(top_pose, bottom_pose, can_height=0.122, max_tilt_deg=10.0, max_offset=0.01,
                max_height_error=0.01):
    """Whether the top can stands on the bottom one: poses ((x, y, z), (qx, qy, qz, qw)) of the
    cans' centres in the world. Success = tilt < max_tilt_deg, horizontal centre offset <
    max_offset, and the top centre one can height above the bottom centre (+- max_height_error)."""
    (tp, tq), (bp, _) = top_pose, bottom_pose
    tilt = math.degrees(tilt_of(tq))
    offset = math.hypot(tp[0] - bp[0], tp[1] - bp[1])
    dz = (tp[2] - bp[2]) - can_height
    ok = tilt < max_tilt_deg and offset < max_offset and abs(dz) < max_height_error
    text = ("stands" if ok else "does not stand") + (
        ": tilt %.1f deg (< %.0f), centres %.1f mm apart (< %.0f), height error %.1f mm"
        % (tilt, max_tilt_deg, offset * 1000, max_offset * 1000, dz * 1000))
    return StackOutcome(ok, tilt, offset, dz, text)

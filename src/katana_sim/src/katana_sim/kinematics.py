"""Katana 450 (6M90A) kinematics, pure numpy: forward kinematics of the five arm joints with
katana_description's joint frames, the seed's triangle IK (seed 001, section 4.4 B) and a closed-form
grasp IK (tool horizontal, pointing away from the base).

Frames: positions are in ``katana_base_link`` (z up, the pan axis through the origin); the
shoulder (``katana_base_frame``) is ``BASE_HEIGHT`` above it. The tool point is
``katana_gripper_tool_frame`` (its z axis is the gripper's approach direction).

The 6M90A's gripper stands at 90 degrees to the wrist: from joint 4 the tool is ``LINK4`` along
the wrist and ``LINK5`` across it, which is why the seed corrects joint 4 by atan(D / C).
"""
import math

import numpy as np

from katana_sim.errors import UnreachableError

JOINTS = ("katana_motor1_pan_joint", "katana_motor2_lift_joint", "katana_motor3_lift_joint",
          "katana_motor4_lift_joint", "katana_motor5_wrist_roll_joint")
FINGERS = ("katana_r_finger_joint", "katana_l_finger_joint")
BASE_HEIGHT = 0.2015
LINK2 = 0.19
LINK3 = 0.139
LINK4 = 0.1473
LINK5 = 0.1505
#: katana_description's position limits (rad)
LOWER = (-3.025528, -0.135228, -2.221804, -2.033309, -2.993240)
UPPER = (2.891097, 2.168572, 2.054223, 1.876133, 2.870985)
#: a folded rest pose: gripper up, above the base, out of the laser's plane and the cans' way
HOME = (0.0, 2.0, -2.0, -1.4, 0.0)


def _rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _rpy(r, p, y):
    cr, sr, cp, sp = math.cos(r), math.sin(r), math.cos(p), math.sin(p)
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    return _rot_z(y).dot(ry).dot(np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]]))


def _tf(xyz, rot):
    t = np.eye(4)
    t[:3, :3] = rot
    t[:3, 3] = xyz
    return t


# joint origins (parent link frame -> joint frame), katana_description's values
_ORIGINS = (
    _tf((0, 0, BASE_HEIGHT), np.eye(3)),
    _tf((0, 0, 0), _rpy(math.pi / 2, 0, 0)),
    _tf((LINK2, 0, 0), np.eye(3)),
    _tf((LINK3, 0, 0), _rpy(math.pi, 0, 0)),
    _tf((LINK4, 0, 0), _rpy(math.pi / 2, 0, -math.pi / 2)),
)
_TOOL = _tf((LINK5, 0, 0), _rpy(0, math.pi / 2, 0))


def link_frames(q):
    """World (katana_base_link) 4x4 transforms of the five moving links and the tool frame."""
    q = check_joints(q)
    t = np.eye(4)
    out = []
    for origin, angle in zip(_ORIGINS, q):
        t = t.dot(origin).dot(_tf((0, 0, 0), _rot_z(angle)))
        out.append(t)
    out.append(t.dot(_TOOL))
    return out


def fk(q):
    """4x4 transform of katana_gripper_tool_frame in katana_base_link."""
    return link_frames(q)[-1]


def tool_position(q):
    return fk(q)[:3, 3].copy()


def check_joints(q):
    q = [float(v) for v in q]
    if len(q) != 5:
        raise ValueError("the Katana has 5 arm joints, got %d values" % len(q))
    if not all(math.isfinite(v) for v in q):
        raise ValueError("joint values must be finite, got %s" % q)
    return q


def within_limits(q, margin=0.0):
    return all(lo + margin <= v <= hi - margin for v, lo, hi in zip(q, LOWER, UPPER))


def limit_violations(q):
    return ["%s = %.3f outside [%.3f, %.3f]" % (n, v, lo, hi)
            for n, v, lo, hi in zip(JOINTS, q, LOWER, UPPER) if not lo <= v <= hi]


def _check_target(p):
    p = [float(v) for v in p]
    if len(p) != 3 or not all(math.isfinite(v) for v in p):
        raise UnreachableError("target must be three finite numbers (x y z in katana_base_link), got %s"
                               % (p,))
    return p


# ------------------------------------------------------------------------------------------------
# the seed's base-angle quadrant rule (4.4 B)
def seed_base_angle(x, y):
    """The seed's joint-1 angle with its quadrant handling, as written:
    y > 0: atan(x / y); else x < 0: atan(x / y) - pi; else atan(x / y) + pi.
    The seed measures the angle from its y axis towards its x axis (its frame is the laser
    formula's: y ahead, x to the side). ``pan_angle`` turns it into the katana's joint 1."""
    if y > 0:
        return math.atan(x / y)
    if y == 0:
        return math.copysign(math.pi / 2, x) if x != 0 else 0.0
    if x < 0:
        return math.atan(x / y) - math.pi
    return math.atan(x / y) + math.pi


def pan_angle(x, y):
    """Joint 1 for a target at (x, y) of katana_base_link (x ahead, y left): the seed's rule fed with
    the seed frame's coordinates (x_s, y_s) = (-y, x), i.e. its angle measured from ahead towards
    the right, negated into the katana's counter-clockwise joint 1. Equals atan2(y, x)."""
    return -seed_base_angle(-y, x)


# ------------------------------------------------------------------------------------------------
# the seed's triangle: shoulder -> elbow (LINK2), elbow -> tool with joint 4 set so that the tool lies
# on the forearm's line: the wrist and the 90-degree gripper form a right triangle with legs
# LINK4 (C) and LINK5 (D), so joint 4 turns by atan(D / C) and the side BC = LINK3 + hypot(C, D)
TRIANGLE_Q4 = math.atan2(LINK5, LINK4)
TRIANGLE_BC = LINK3 + math.hypot(LINK4, LINK5)


def triangle_ik(target, q5=0.0):
    """Seed 001 section 4.4 B: the arm as a triangle. Returns the five joint angles putting the tool
    point at ``target`` (x, y, z in katana_base_link), or raises UnreachableError with the reason.

    joint 1: the base angle with the seed's quadrant rule;
    the triangle: side A = LINK2 (shoulder to elbow), side BC = elbow to the gripper point (the
    wrist turned by atan(D / C) so that the gripper point continues the forearm), and the distance
    from the shoulder to the target; 'dip' = the angle of that distance below the horizontal
    (the seed's arccos(distance_top / distance), negative when the target is higher);
    joint 2 = alpha - dip, joint 3 = pi - (the triangle's elbow angle) with the katana's sign,
    joint 4 = the atan(D / C) correction, joint 5 unused (0)."""
    x, y, z = _check_target(target)
    q1 = pan_angle(x, y)
    distance_top = math.hypot(x, y)
    height = z - BASE_HEIGHT
    distance = math.hypot(distance_top, height)
    a, b = LINK2, TRIANGLE_BC
    if distance > a + b:
        raise UnreachableError("target (%.3f, %.3f, %.3f) is %.3f m from the shoulder; the triangle reaches "
                               "%.3f m at most" % (x, y, z, distance, a + b))
    if distance < abs(a - b):
        raise UnreachableError("target (%.3f, %.3f, %.3f) is %.3f m from the shoulder; closer than %.3f m "
                               "cannot be reached with the gripper on the forearm's line"
                               % (x, y, z, distance, abs(a - b)))
    if distance_top < 1e-9:
        raise UnreachableError("target (%.3f, %.3f, %.3f) is on the pan axis: the base angle is undefined"
                               % (x, y, z))
    dip = math.acos(max(-1.0, min(1.0, distance_top / distance)))
    if height > 0:
        dip = -dip
    # law of cosines: alpha at the shoulder, gamma at the elbow
    alpha = math.acos(max(-1.0, min(1.0, (a * a + distance * distance - b * b) / (2 * a * distance))))
    gamma = math.acos(max(-1.0, min(1.0, (a * a + b * b - distance * distance) / (2 * a * b))))
    # elbow up: the upper arm rises by alpha above the line to the target, the forearm comes back down
    q2 = alpha - dip
    q3 = -(math.pi - gamma)
    q = [q1, q2, q3, TRIANGLE_Q4, q5]
    bad = limit_violations(q)
    if bad:
        raise UnreachableError("target (%.3f, %.3f, %.3f): the triangle solution breaks joint limits: %s"
                               % (x, y, z, "; ".join(bad)))
    return q


def grasp_ik(target, approach_pitch=0.0, q5=0.0):
    """Closed-form IK with the gripper's approach axis fixed in the vertical plane through the base:
    ``approach_pitch`` 0 = horizontal, pointing away from the base (the side grasp of a standing
    can); positive pitches it down. Joint 5 = q5 (0: the finger hinges vertical when horizontal).
    Raises UnreachableError with the reason."""
    x, y, z = _check_target(target)
    r = math.hypot(x, y)
    if r < 1e-9:
        raise UnreachableError("target (%.3f, %.3f, %.3f) is on the pan axis" % (x, y, z))
    q1 = pan_angle(x, y)
    h = z - BASE_HEIGHT
    # approach direction in the arm plane (r, h) and the wrist direction: the gripper (LINK5) lies
    # along the approach, the wrist (LINK4) perpendicular to it, the wrist roll housing above it
    ar, ah = math.cos(approach_pitch), -math.sin(approach_pitch)
    wr, wh = -ah, ar    # unit vector from the tool's wrist corner up to joint 4 (perpendicular, upwards)
    j4r = r - LINK5 * ar + LINK4 * wr
    j4h = h - LINK5 * ah + LINK4 * wh
    d = math.hypot(j4r, j4h)
    if d > LINK2 + LINK3:
        raise UnreachableError("target (%.3f, %.3f, %.3f): the wrist would be %.3f m from the shoulder, "
                               "more than the arm's %.3f m" % (x, y, z, d, LINK2 + LINK3))
    if d < abs(LINK2 - LINK3):
        raise UnreachableError("target (%.3f, %.3f, %.3f): the wrist would be %.3f m from the shoulder, "
                               "closer than %.3f m" % (x, y, z, d, abs(LINK2 - LINK3)))
    c3 = (d * d - LINK2 * LINK2 - LINK3 * LINK3) / (2 * LINK2 * LINK3)
    e = math.acos(max(-1.0, min(1.0, c3)))
    # elbow up: link 2 above the line to the wrist
    phi = math.atan2(j4h, j4r)
    beta = math.atan2(LINK3 * math.sin(e), LINK2 + LINK3 * math.cos(e))
    q2 = phi + beta
    q3 = -e
    # joint 4: the wrist (x4) must point from joint 4 to the tool's corner, i.e. along -w
    forearm = q2 + q3                         # direction of link 3 in the plane (from the r axis)
    wrist_dir = math.atan2(-wh, -wr)          # direction of link 4 wanted
    q4 = _wrap(-(wrist_dir - forearm))        # joint 4 turns the other way (its frame is flipped)
    q = [q1, q2, q3, q4, q5]
    bad = limit_violations(q)
    if bad:
        raise UnreachableError("target (%.3f, %.3f, %.3f): the grasp posture breaks joint limits: %s"
                               % (x, y, z, "; ".join(bad)))
    return q


def _wrap(a):
    return math.atan2(math.sin(a), math.cos(a))

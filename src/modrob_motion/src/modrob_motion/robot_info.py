"""What the motion interface needs to know about one robot, read from its URDF.

Pure (xml.etree only): the movable joints in kinematic order (root to tip), their limits, which
of them are the gripper's fingers and the finger positions that mean "open" and "closed".
"""
import math
import xml.etree.ElementTree as ET

from modrob_motion.errors import MotionError
from modrob_motion.joint_matching import JointLimits

MOVABLE = ("revolute", "continuous", "prismatic")


def _floats(text, default):
    if text is None:
        return list(default)
    try:
        vals = [float(v) for v in text.split()]
    except ValueError:
        return list(default)
    return vals if len(vals) == 3 else list(default)


def _rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]]


def _mat_vec(m, v):
    return [sum(m[i][k] * v[k] for k in range(3)) for i in range(3)]


class UrdfJoint(object):
    __slots__ = ("name", "type", "parent", "child", "xyz", "rpy", "axis", "limits", "effort", "mimic")

    def __init__(self, elem):
        self.name = elem.get("name")
        self.type = elem.get("type")
        self.parent = elem.find("parent").get("link") if elem.find("parent") is not None else None
        self.child = elem.find("child").get("link") if elem.find("child") is not None else None
        origin = elem.find("origin")
        self.xyz = _floats(origin.get("xyz") if origin is not None else None, (0, 0, 0))
        self.rpy = _floats(origin.get("rpy") if origin is not None else None, (0, 0, 0))
        axis = elem.find("axis")
        self.axis = _floats(axis.get("xyz") if axis is not None else None, (1, 0, 0))
        lim = elem.find("limit")
        lower = upper = None
        if lim is not None and self.type in ("revolute", "prismatic"):
            lower = float(lim.get("lower", 0.0))
            upper = float(lim.get("upper", 0.0))
        self.limits = JointLimits(lower, upper)
        # <limit effort>: the largest effort the simulator applies (a gripper's grip force); None if not given
        self.effort = float(lim.get("effort")) if lim is not None and lim.get("effort") is not None else None
        self.mimic = elem.find("mimic") is not None


class GripperSpec(object):
    """The gripper's actuated finger joints and their open/closed commands."""

    def __init__(self, joints, open_positions, closed_positions):
        self.joints = list(joints)
        self.open_positions = dict(open_positions)
        self.closed_positions = dict(closed_positions)

    def command(self, action):
        if action == "open":
            return dict(self.open_positions)
        if action == "close":
            return dict(self.closed_positions)
        raise MotionError("gripper action must be 'open' or 'close', not %r" % (action,))


class RobotInfo(object):
    """robot_id, arm_joints (chain order, no fingers), limits, home, gripper (GripperSpec|None)."""

    def __init__(self, robot_id, arm_joints, limits, gripper=None, home=None, namespace=None):
        self.robot_id = robot_id
        self.arm_joints = list(arm_joints)
        self.limits = dict(limits)
        self.gripper = gripper
        self.namespace = namespace or "/modrob%d" % robot_id
        if home is None:
            home = []
            for j in self.arm_joints:   # zero, or the nearest limit when zero is outside them
                lim = self.limits.get(j)
                q = 0.0
                if lim is not None and lim.lower is not None and q < lim.lower:
                    q = lim.lower
                if lim is not None and lim.upper is not None and q > lim.upper:
                    q = lim.upper
                home.append(q)
        if len(home) != len(self.arm_joints):
            raise MotionError("robot %d: home has %d values but the arm has %d joints"
                              % (robot_id, len(home), len(self.arm_joints)))
        self.home = [float(h) for h in home]

    @property
    def all_joints(self):
        return self.arm_joints + (self.gripper.joints if self.gripper else [])


def parse_urdf_joints(urdf_xml):
    try:
        root = ET.fromstring(urdf_xml)
    except ET.ParseError as exc:
        raise MotionError("robot description is not valid XML: %s" % exc)
    if root.tag != "robot":
        raise MotionError("robot description's root element is <%s>, expected <robot>" % root.tag)
    return [UrdfJoint(j) for j in root.findall("joint")]


def chain_order(joints):
    """Movable joints in depth-first order from the root link (a chain's order, root to tip)."""
    by_parent = {}
    children = set()
    for j in joints:
        by_parent.setdefault(j.parent, []).append(j)
        children.add(j.child)
    roots = [p for p in by_parent if p not in children]
    order = []

    def visit(link):
        for j in by_parent.get(link, []):
            if j.type in MOVABLE:
                order.append(j)
            visit(j.child)
    for r in roots:
        visit(r)
    return order


def _is_finger(j):
    return j.type == "prismatic" and ("finger" in j.name.lower() or "finger" in (j.child or "").lower())


def gripper_from_joints(movable):
    """GripperSpec for the prismatic finger joints (names containing 'finger'), or None.

    Open/closed per finger: of its two limits, "closed" is the one that brings the finger nearer
    the other finger(s) (each other finger taken at the middle of its travel), "open" the other.
    """
    fingers = [j for j in movable if _is_finger(j) and not j.mimic]
    all_fingers = [j for j in movable if _is_finger(j)]
    if not fingers:
        return None
    open_pos, closed_pos = {}, {}
    for f in fingers:
        if f.limits.lower is None or f.limits.upper is None:
            raise MotionError("gripper finger joint '%s' has no <limit lower upper>: cannot tell open "
                              "from closed" % f.name)
        others = [o for o in all_fingers if o is not f]

        def tip(j, q):
            d = _mat_vec(_rpy_matrix(*j.rpy), j.axis)
            return [j.xyz[i] + d[i] * q for i in range(3)]
        if others:
            centre = [0.0, 0.0, 0.0]
            for o in others:
                mid = 0.5 * ((o.limits.lower or 0.0) + (o.limits.upper or 0.0))
                centre = [c + t / len(others) for c, t in zip(centre, tip(o, mid))]
        else:
            centre = [0.0, 0.0, 0.0]

        def dist(q):
            return math.sqrt(sum((a - b) ** 2 for a, b in zip(tip(f, q), centre)))
        lo, hi = f.limits.lower, f.limits.upper
        if dist(lo) <= dist(hi):
            closed_pos[f.name], open_pos[f.name] = lo, hi
        else:
            closed_pos[f.name], open_pos[f.name] = hi, lo
    return GripperSpec([f.name for f in fingers], open_pos, closed_pos)


def robot_info_from_urdf(robot_id, urdf_xml, home=None, namespace=None):
    """RobotInfo from a URDF string. Mimic joints are left out (they follow their leader)."""
    movable = chain_order(parse_urdf_joints(urdf_xml))
    gripper = gripper_from_joints(movable)
    finger_names = set(gripper.joints) if gripper else set()
    arm = [j for j in movable if j.name not in finger_names and not j.mimic and not _is_finger(j)]
    limits = {j.name: j.limits for j in movable}
    if not arm:
        raise MotionError("robot %d: its description has no movable arm joint" % robot_id)
    return RobotInfo(robot_id, [j.name for j in arm], limits, gripper=gripper, home=home, namespace=namespace)

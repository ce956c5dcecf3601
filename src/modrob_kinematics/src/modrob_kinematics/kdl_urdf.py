"""KDL kinematics from a URDF string, without rospy.

kdl_parser_py is not packaged for this machine, so :func:`tree_from_urdf_string` does what
kdl_parser (C++) does, with ``urdf_parser_py`` reading the XML:

* every link except the root becomes a ``PyKDL.Segment`` named after the link, whose joint is
  the link's parent joint: ``revolute``/``continuous`` -> ``Joint.RotAxis`` and ``prismatic`` ->
  ``Joint.TransAxis`` about/along the joint axis expressed in the parent frame, ``fixed`` ->
  ``Joint.Fixed``; the segment's tip frame is the joint origin (xyz + rpy);
* the inertia is the link's ``<inertial>`` rotated into the link frame, about the COM at the
  inertial origin;
* ``floating`` and ``planar`` joints become fixed joints with a warning (as kdl_parser does);
  mimic joints are kept as independent joints.

The Debian PyKDL (pybind11 bindings, KDL 1.5) offers ``Tree`` but neither tree traversal nor
``TreeFkSolverPos_recursive``. :class:`TreeFkSolverPos` is that solver's algorithm on the
segments kept here (walk from the requested segment up to the root, composing
``segment.pose(q)``); :class:`KinematicChain` uses ``Tree.getChain`` and KDL's own chain solvers
(``ChainFkSolverPos_recursive``, ``ChainIkSolverPos_LMA``) for FK and IK.
"""
import math
import random

import numpy as np
import PyKDL

from modrob_kinematics.errors import KinematicsError, UnreachableError, UrdfError

MOVABLE_TYPES = ("revolute", "continuous", "prismatic")


class SegmentInfo(object):
    """What the tree knows about one segment (= one non-root link)."""

    def __init__(self, segment, parent, joint_name, joint_type, q_nr, inertia_matrix):
        self.segment = segment          # PyKDL.Segment
        self.parent = parent            # name of the parent segment (or the root link)
        self.joint_name = joint_name    # URDF name of the joint into this link
        self.joint_type = joint_type    # URDF type: fixed, revolute, continuous, prismatic ...
        self.q_nr = q_nr                # index into the tree's joint vector, None if fixed
        self.inertia_matrix = inertia_matrix  # 3x3 about the COM, in the link frame (numpy)


class KdlTree(object):
    """A ``PyKDL.Tree`` plus the bookkeeping the Python bindings do not expose."""

    def __init__(self, robot_name, root):
        self.robot_name = robot_name
        self.root = root
        self.tree = PyKDL.Tree(root)
        self.segments = {}        # link name -> SegmentInfo
        self.joint_names = []     # movable joints in KDL's q_nr order
        self.limits = {}          # joint name -> (lower, upper); continuous: (-inf, inf)
        self.joint_types = {}     # every URDF joint name -> type
        self.warnings = []        # things converted with a loss (floating joints ...)
        self.parser_notes = []    # urdf_parser_py's remarks on tags it ignores

    @property
    def link_names(self):
        return [self.root] + list(self.segments)

    def has_link(self, name):
        return name == self.root or name in self.segments

    def path_to_root(self, link):
        """Segment names from ``link`` up to (not including) the root."""
        if not self.has_link(link):
            raise KinematicsError("link '%s' is not in robot '%s' (links: %s)"
                                  % (link, self.robot_name, ", ".join(sorted(self.link_names))))
        path = []
        while link != self.root:
            path.append(link)
            link = self.segments[link].parent
        return path

    def joints_between(self, base, tip):
        """Movable joint names on the path base -> tip, in order from the base."""
        up_tip = self.path_to_root(tip)
        self.path_to_root(base)  # validates the name
        if base == tip:
            return []
        if base != self.root and base not in up_tip:
            raise KinematicsError("link '%s' is not an ancestor of link '%s' in robot '%s'"
                                  % (base, tip, self.robot_name))
        below = up_tip[:up_tip.index(base)] if base != self.root else up_tip
        return [self.segments[s].joint_name for s in reversed(below)
                if self.segments[s].q_nr is not None]


def _vector(xyz):
    return PyKDL.Vector(*[float(v) for v in (xyz or (0.0, 0.0, 0.0))])


def _frame(origin):
    if origin is None:
        return PyKDL.Frame.Identity()
    rpy = origin.rpy or (0.0, 0.0, 0.0)
    return PyKDL.Frame(PyKDL.Rotation.RPY(*[float(v) for v in rpy]), _vector(origin.xyz))


def _rotation_matrix(rot):
    return np.array([[rot[i, j] for j in range(3)] for i in range(3)])


def _inertia(link):
    """(PyKDL.RigidBodyInertia, 3x3 inertia about the COM in the link frame)."""
    inertial = link.inertial
    if inertial is None:
        return PyKDL.RigidBodyInertia(), np.zeros((3, 3))
    frame = _frame(inertial.origin)
    i = inertial.inertia
    if i is None:
        ic = np.zeros((3, 3))
    else:
        ic = np.array([[i.ixx, i.ixy, i.ixz], [i.ixy, i.iyy, i.iyz], [i.ixz, i.iyz, i.izz]], dtype=float)
    rot = _rotation_matrix(frame.M)
    ic_link = rot.dot(ic).dot(rot.T)
    mass = float(inertial.mass or 0.0)
    if not (math.isfinite(mass) and np.all(np.isfinite(ic_link))):
        raise UrdfError("link '%s' has a non-finite mass or inertia" % link.name)
    rot_inertia = PyKDL.RotationalInertia(ic_link[0, 0], ic_link[1, 1], ic_link[2, 2],
                                          ic_link[0, 1], ic_link[0, 2], ic_link[1, 2])
    return PyKDL.RigidBodyInertia(mass, frame.p, rot_inertia), ic_link


def _kdl_joint(joint, origin, warnings):
    jtype = joint.type
    if jtype in MOVABLE_TYPES:
        axis = np.array(joint.axis if joint.axis is not None else (1.0, 0.0, 0.0), dtype=float)
        norm = np.linalg.norm(axis)
        if not math.isfinite(norm) or norm < 1e-12:
            raise UrdfError("joint '%s' has a zero or invalid <axis xyz=\"%s\"/>: give a unit vector"
                            % (joint.name, " ".join(str(a) for a in axis)))
        axis_parent = origin.M * PyKDL.Vector(*(axis / norm))
        kind = PyKDL.Joint.TransAxis if jtype == "prismatic" else PyKDL.Joint.RotAxis
        return PyKDL.Joint(joint.name, origin.p, axis_parent, kind)
    if jtype != "fixed":
        warnings.append("joint '%s' of type '%s' is treated as fixed (KDL has no such joint)"
                        % (joint.name, jtype))
    return PyKDL.Joint(joint.name, PyKDL.Joint.Fixed)


def _limits(joint):
    if joint.type == "continuous":
        return (-math.inf, math.inf)
    limit = joint.limit
    if limit is None or limit.lower is None or limit.upper is None:
        raise UrdfError("%s joint '%s' has no <limit lower=... upper=...>: add one (as check_urdf "
                        "requires)" % (joint.type, joint.name))
    lower, upper = float(limit.lower), float(limit.upper)
    if not (lower <= upper):
        raise UrdfError("joint '%s' has lower limit %g above upper limit %g"
                        % (joint.name, lower, upper))
    if lower == upper == 0.0:  # urdfdom's convention for "no limits given"
        return (-math.inf, math.inf) if joint.type != "prismatic" else (0.0, 0.0)
    return (lower, upper)


def parse_urdf(xml, notes=None):
    """``urdf_parser_py`` robot from a URDF string; errors become :class:`UrdfError`.

    urdf_parser_py's remarks about tags it does not model (``<transmission>`` details,
    ``<gazebo>``) go to the list ``notes`` instead of stderr.
    """
    from urdf_parser_py.urdf import URDF  # from the workspace venv (PyPI urdfdom-py)
    from urdf_parser_py.xml_reflection import core
    if not isinstance(xml, str) or not xml.strip():
        raise UrdfError("the robot description is empty: load a URDF into robot_description")
    saved = core.on_error
    core.on_error = (notes.append if notes is not None else (lambda message: None))
    try:
        robot = URDF.from_xml_string(xml)
    except Exception as err:  # lxml syntax errors, urdf_parser_py assertion/value errors
        raise UrdfError("the robot description is not a valid URDF: %s" % err)
    finally:
        core.on_error = saved
    return robot


def tree_from_urdf_string(xml):
    """A :class:`KdlTree` from a URDF string (what kdl_parser's treeFromString does)."""
    notes = []
    kdl = tree_from_urdf_model(parse_urdf(xml, notes))
    kdl.parser_notes = notes
    return kdl


def tree_from_urdf_model(robot):
    """A :class:`KdlTree` from an ``urdf_parser_py`` robot."""
    if not robot.links:
        raise UrdfError("robot '%s' has no links" % robot.name)
    for joint in robot.joints:
        for role, link in (("parent", joint.parent), ("child", joint.child)):
            if link not in robot.link_map:
                raise UrdfError("joint '%s' names %s link '%s', which robot '%s' does not define"
                                % (joint.name, role, link, robot.name))
    children = {}
    for joint in robot.joints:
        if joint.child in children:
            raise UrdfError("link '%s' is the child of two joints ('%s' and '%s')"
                            % (joint.child, children[joint.child].name, joint.name))
        children[joint.child] = joint
    roots = [link.name for link in robot.links if link.name not in children]
    if len(roots) != 1:
        raise UrdfError("robot '%s' must have exactly one root link, found %d (%s)"
                        % (robot.name, len(roots), ", ".join(roots) or "a cycle"))
    kdl = KdlTree(robot.name, roots[0])
    child_map = {}
    for joint in robot.joints:
        child_map.setdefault(joint.parent, []).append(joint)
    stack = [roots[0]]
    seen = set(stack)
    while stack:  # depth-first in document order, as kdl_parser adds segments
        parent = stack.pop(0)
        new = []
        for joint in child_map.get(parent, []):
            if joint.child in seen:
                raise UrdfError("the joints of robot '%s' form a cycle at link '%s'"
                                % (robot.name, joint.child))
            seen.add(joint.child)
            _add_segment(kdl, robot, joint)
            new.append(joint.child)
        stack[0:0] = new
    return kdl


def _add_segment(kdl, robot, joint):
    origin = _frame(joint.origin)
    kdl_joint = _kdl_joint(joint, origin, kdl.warnings)
    rbi, ic = _inertia(robot.link_map[joint.child])
    segment = PyKDL.Segment(joint.child, kdl_joint, origin, rbi)
    if not kdl.tree.addSegment(segment, joint.parent):
        raise UrdfError("KDL refused segment '%s' below '%s'" % (joint.child, joint.parent))
    kdl.joint_types[joint.name] = joint.type
    q_nr = None
    if joint.type in MOVABLE_TYPES:
        q_nr = len(kdl.joint_names)
        kdl.joint_names.append(joint.name)
        kdl.limits[joint.name] = _limits(joint)
    kdl.segments[joint.child] = SegmentInfo(segment, joint.parent, joint.name, joint.type, q_nr, ic)


# ---------------------------------------------------------------- conversions

def frame_to_matrix(frame):
    """4x4 homogeneous numpy matrix of a ``PyKDL.Frame``."""
    m = np.eye(4)
    m[:3, :3] = _rotation_matrix(frame.M)
    m[:3, 3] = [frame.p[0], frame.p[1], frame.p[2]]
    return m


def frame_to_pose(frame):
    """((x, y, z), (qx, qy, qz, qw)) of a ``PyKDL.Frame``."""
    return (frame.p[0], frame.p[1], frame.p[2]), frame.M.GetQuaternion()


def to_frame(target):
    """A ``PyKDL.Frame`` from a Frame, a 4x4 matrix, ((x, y, z), (qx, qy, qz, qw)) or (x, y, z).

    Returns (frame, position_only): a bare position sets ``position_only``.
    """
    if isinstance(target, PyKDL.Frame):
        return target, False
    arr = np.asarray(target, dtype=object)
    if arr.shape == (3,):
        xyz = [float(v) for v in target]
        _check_finite(xyz, "IK target position")
        return PyKDL.Frame(PyKDL.Vector(*xyz)), True
    if arr.shape == (4, 4):
        m = np.asarray(target, dtype=float)
        _check_finite(m.ravel(), "IK target matrix")
        rot = PyKDL.Rotation(*m[:3, :3].ravel())
        return PyKDL.Frame(rot, PyKDL.Vector(*m[:3, 3])), False
    if len(target) == 2 and len(target[0]) == 3 and len(target[1]) == 4:
        xyz = [float(v) for v in target[0]]
        quat = [float(v) for v in target[1]]
        _check_finite(xyz + quat, "IK target pose")
        n = math.sqrt(sum(v * v for v in quat))
        if n < 1e-9:
            raise KinematicsError("IK target quaternion is zero")
        return PyKDL.Frame(PyKDL.Rotation.Quaternion(*[v / n for v in quat]), PyKDL.Vector(*xyz)), False
    raise KinematicsError("IK target must be (x, y, z), ((x, y, z), (qx, qy, qz, qw)), a 4x4 matrix "
                          "or a PyKDL.Frame, got %r" % (target,))


def _check_finite(values, what):
    for v in values:
        if not math.isfinite(float(v)):
            raise KinematicsError("%s contains a non-finite value (%r)" % (what, list(values)))


# ---------------------------------------------------------------- solvers

class TreeFkSolverPos(object):
    """KDL's ``TreeFkSolverPos_recursive`` for Python: the pose of any segment relative to the
    tree root for joint positions given by name (dict) or in the tree's q_nr order (sequence)."""

    def __init__(self, kdl_tree):
        self.kdl = kdl_tree

    def joint_vector(self, q):
        if isinstance(q, dict):
            values = [0.0] * len(self.kdl.joint_names)
            index = {n: i for i, n in enumerate(self.kdl.joint_names)}
            for name, value in q.items():
                if name not in index:
                    raise KinematicsError("joint '%s' is not a movable joint of robot '%s' (joints: %s)"
                                          % (name, self.kdl.robot_name, ", ".join(self.kdl.joint_names)))
                values[index[name]] = float(value)
        else:
            values = [float(v) for v in q]
            if len(values) != len(self.kdl.joint_names):
                raise KinematicsError("robot '%s' has %d movable joints, got %d positions"
                                      % (self.kdl.robot_name, len(self.kdl.joint_names), len(values)))
        _check_finite(values, "joint positions")
        return values

    def jnt_to_cart(self, q, segment_name):
        """``PyKDL.Frame`` of ``segment_name`` in the root frame."""
        values = self.joint_vector(q)
        frame = PyKDL.Frame.Identity()
        for name in self.kdl.path_to_root(segment_name):
            info = self.kdl.segments[name]
            qi = values[info.q_nr] if info.q_nr is not None else 0.0
            frame = info.segment.pose(qi) * frame
        return frame


class KinematicChain(object):
    """The chain from ``base_link`` to ``tip_link`` of a robot: FK and IK with KDL.

    ``joint_names`` lists the chain's movable joints from the base; ``lower``/``upper`` their
    limits (continuous joints: -inf/inf).
    """

    def __init__(self, kdl_tree, base_link, tip_link):
        self.kdl = kdl_tree
        self.base_link = base_link
        self.tip_link = tip_link
        self.joint_names = kdl_tree.joints_between(base_link, tip_link)  # validates both links
        self.chain = kdl_tree.tree.getChain(base_link, tip_link)
        if self.chain.getNrOfJoints() != len(self.joint_names):
            raise KinematicsError("KDL chain %s -> %s has %d joints, expected %d"
                                  % (base_link, tip_link, self.chain.getNrOfJoints(), len(self.joint_names)))
        self.lower = [kdl_tree.limits[n][0] for n in self.joint_names]
        self.upper = [kdl_tree.limits[n][1] for n in self.joint_names]
        self._fk = PyKDL.ChainFkSolverPos_recursive(self.chain)
        self.reach = self._reach_bound()

    @classmethod
    def from_urdf_string(cls, xml, base_link=None, tip_link=None):
        """Chain of a URDF string; ``base_link`` defaults to the root, ``tip_link`` to the last
        link of the longest root-to-leaf path."""
        tree = tree_from_urdf_string(xml)
        base = base_link or tree.root
        tip = tip_link or default_tip_link(tree)
        return cls(tree, base, tip)

    @property
    def n_joints(self):
        return len(self.joint_names)

    def _reach_bound(self):
        """An upper bound of the distance the tip can be from the base origin [m]."""
        total = 0.0
        for i in range(self.chain.getNrOfSegments()):
            seg = self.chain.getSegment(i)
            total += seg.pose(0.0).p.Norm()
        for name, lo, hi in zip(self.joint_names, self.lower, self.upper):
            if self.kdl.joint_types[name] == "prismatic":
                total += max(abs(lo), abs(hi))
        return total

    def _jnt_array(self, q):
        values = [float(v) for v in q]
        if len(values) != self.n_joints:
            raise KinematicsError("chain %s -> %s has %d joints (%s), got %d positions"
                                  % (self.base_link, self.tip_link, self.n_joints,
                                     ", ".join(self.joint_names), len(values)))
        _check_finite(values, "joint positions")
        arr = PyKDL.JntArray(self.n_joints)
        for i, v in enumerate(values):
            arr[i] = v
        return arr

    def fk(self, q):
        """``PyKDL.Frame`` of the tip in the base frame."""
        frame = PyKDL.Frame()
        rc = self._fk.JntToCart(self._jnt_array(q), frame)
        if rc < 0:
            raise KinematicsError("KDL forward kinematics failed with code %d" % rc)
        return frame

    def fk_matrix(self, q):
        return frame_to_matrix(self.fk(q))

    def fk_pose(self, q):
        return frame_to_pose(self.fk(q))

    def fk_position(self, q):
        p = self.fk(q).p
        return (p[0], p[1], p[2])

    def within_limits(self, q, tol=1e-9):
        return all(lo - tol <= v <= hi + tol for v, lo, hi in zip(q, self.lower, self.upper))

    def _wrap_into_limits(self, q):
        """Shift revolute angles by multiples of 2 pi into their limits where that is possible."""
        out = list(q)
        for i, name in enumerate(self.joint_names):
            if self.kdl.joint_types[name] == "prismatic":
                continue
            lo, hi = self.lower[i], self.upper[i]
            v = out[i]
            if math.isinf(lo) and math.isinf(hi):
                v = math.atan2(math.sin(v), math.cos(v))
            else:
                while v > hi and v - 2 * math.pi >= lo - 1e-9:
                    v -= 2 * math.pi
                while v < lo and v + 2 * math.pi <= hi + 1e-9:
                    v += 2 * math.pi
            out[i] = v
        return out

    def _error(self, q, target, position_only):
        frame = self.fk(q)
        pos_err = (frame.p - target.p).Norm()
        if position_only:
            return pos_err, 0.0
        twist = PyKDL.diff(frame, target)
        return pos_err, twist.rot.Norm()

    def ik(self, target, q0=None, position_only=None, tol=1e-4, rot_tol=1e-3, attempts=20, seed=0):
        """Joint positions (list, chain order) that put the tip at ``target`` within the limits.

        ``target``: (x, y, z) (position only), ((x, y, z), (qx, qy, qz, qw)), a 4x4 matrix or a
        ``PyKDL.Frame``. ``q0`` is the start (defaults to the middle of the limits). Levenberg-
        Marquardt (``ChainIkSolverPos_LMA``, orientation weighted 0 for position targets) runs
        from ``q0`` and then from up to ``attempts - 1`` starts drawn from a generator seeded
        with ``seed``. LMA knows no joint limits: when its answer lies outside them, a damped
        least-squares solve projected onto the limits continues from the clamped answer (on a
        redundant arm an in-limit solution is usually close by). A result is accepted only if it
        lies within the joint limits and its FK is within ``tol`` [m] (and ``rot_tol`` [rad]) of
        the target. Otherwise raises :class:`UnreachableError` with the best residual found.
        """
        frame, pos_only_default = to_frame(target)
        position_only = pos_only_default if position_only is None else bool(position_only)
        if self.n_joints == 0:
            raise UnreachableError("chain %s -> %s has no movable joint" % (self.base_link, self.tip_link))
        dist = frame.p.Norm()
        if dist > self.reach + tol:
            raise UnreachableError("target (%.3f, %.3f, %.3f) is %.3f m from '%s'; the chain to '%s' "
                                   "reaches at most %.3f m"
                                   % (frame.p[0], frame.p[1], frame.p[2], dist, self.base_link,
                                      self.tip_link, self.reach), residual=dist - self.reach)
        weights = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0] if position_only else [1.0] * 6)
        solver = PyKDL.ChainIkSolverPos_LMA(self.chain, weights, 1e-7, 500, 1e-15)
        rng = random.Random(seed)
        starts = [list(q0) if q0 is not None else self._middle()]
        self._jnt_array(starts[0])  # validates length and finiteness
        for _ in range(max(0, attempts - 1)):
            starts.append(self._random_q(rng))
        best = (math.inf, None)
        for start in starts:
            out = PyKDL.JntArray(self.n_joints)
            solver.CartToJnt(self._jnt_array(start), frame, out)
            q = self._wrap_into_limits([out[i] for i in range(self.n_joints)])
            if not all(math.isfinite(v) for v in q):
                q = self._clamp(start)
            if not self.within_limits(q):
                q = self._projected_dls(self._clamp(q), frame, position_only, tol, rot_tol)
            pos_err, rot_err = self._error(q, frame, position_only)
            if self.within_limits(q) and pos_err < best[0]:
                best = (pos_err, q)
            if pos_err <= tol and rot_err <= rot_tol and self.within_limits(q):
                return q
        what = "position" if position_only else "pose"
        raise UnreachableError("no configuration of %s within the joint limits reaches the target %s "
                               "(%.3f, %.3f, %.3f); best position error %.4f m after %d attempts"
                               % (", ".join(self.joint_names), what, frame.p[0], frame.p[1], frame.p[2],
                                  best[0], len(starts)), residual=best[0])

    def _clamp(self, q):
        return [min(max(v, lo), hi) for v, lo, hi in zip(q, self.lower, self.upper)]

    def _projected_dls(self, q, frame, position_only, tol, rot_tol, iterations=300, damping=0.05):
        """Damped least squares on the KDL Jacobian, each step clamped into the joint limits: the
        iterate never leaves them, so what it converges to is an in-limit answer (or the best
        in-limit approach, for the caller to judge)."""
        jac_solver = PyKDL.ChainJntToJacSolver(self.chain)
        jac = PyKDL.Jacobian(self.n_joints)
        rows = 3 if position_only else 6
        lam2 = damping * damping
        for _ in range(iterations):
            current = self.fk(q)
            if position_only:
                d = frame.p - current.p
                err = np.array([d[0], d[1], d[2]])
                done = np.linalg.norm(err) <= 0.5 * tol
            else:
                tw = PyKDL.diff(current, frame)
                err = np.array([tw.vel[0], tw.vel[1], tw.vel[2], tw.rot[0], tw.rot[1], tw.rot[2]])
                done = np.linalg.norm(err[:3]) <= 0.5 * tol and np.linalg.norm(err[3:]) <= 0.5 * rot_tol
            if done:
                break
            jac_solver.JntToJac(self._jnt_array(q), jac)
            J = np.array([[jac[r, c] for c in range(self.n_joints)] for r in range(rows)])
            dq = J.T @ np.linalg.solve(J @ J.T + lam2 * np.eye(rows), err)
            # active set: a joint on a limit that the step pushes further out is frozen and the
            # others solve for the error without it (plain clamping would stall on the bound)
            pinned = [i for i, (v, lo, hi) in enumerate(zip(q, self.lower, self.upper))
                      if (v <= lo and dq[i] < 0) or (v >= hi and dq[i] > 0)]
            if pinned and len(pinned) < self.n_joints:
                J[:, pinned] = 0.0
                dq = J.T @ np.linalg.solve(J @ J.T + lam2 * np.eye(rows), err)
            step = float(np.max(np.abs(dq)))
            if step > 0.2:                      # keep each step small: the model is linearised
                dq *= 0.2 / step
            q = self._clamp([v + float(d) for v, d in zip(q, dq)])
        return q

    def _middle(self):
        return [0.0 if math.isinf(lo) or math.isinf(hi) else 0.5 * (lo + hi)
                for lo, hi in zip(self.lower, self.upper)]

    def _random_q(self, rng):
        q = []
        for lo, hi in zip(self.lower, self.upper):
            lo = -math.pi if math.isinf(lo) else lo
            hi = math.pi if math.isinf(hi) else hi
            q.append(rng.uniform(lo, hi))
        return q


def default_tip_link(kdl_tree):
    """The deepest link (most segments from the root; first in document order on ties)."""
    best, depth = kdl_tree.root, 0
    for name in kdl_tree.segments:
        d = len(kdl_tree.path_to_root(name))
        if d > depth:
            best, depth = name, d
    return best

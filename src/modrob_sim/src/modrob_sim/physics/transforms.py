"""Small rigid-body transform helpers on plain tuples (fast for single poses; no numpy).

Conventions (the contract's): a pose is ``(position, orientation)`` with position ``(x, y, z)`` and
a unit quaternion ``(x, y, z, w)`` (ROS order). ODE stores quaternions as ``(w, x, y, z)``: use
:func:`to_ode_quat` / :func:`from_ode_quat` at that boundary only.
"""
import math

from ..errors import InputError
from .limits import LENGTH_LIMIT

IDENTITY_QUAT = (0.0, 0.0, 0.0, 1.0)
IDENTITY_POSE = ((0.0, 0.0, 0.0), IDENTITY_QUAT)


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def quat_conj(q):
    return (-q[0], -q[1], -q[2], q[3])


def quat_normalize(q):
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    if not n > 1e-12 or not math.isfinite(n):
        raise InputError("quaternion %r has no usable norm" % (tuple(q),))
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


def quat_rotate(q, v):
    """Rotate vector v by unit quaternion q."""
    qx, qy, qz, qw = q
    vx, vy, vz = v
    # t = 2 * cross(q.xyz, v)
    tx = 2.0 * (qy * vz - qz * vy)
    ty = 2.0 * (qz * vx - qx * vz)
    tz = 2.0 * (qx * vy - qy * vx)
    return (vx + qw * tx + (qy * tz - qz * ty),
            vy + qw * ty + (qz * tx - qx * tz),
            vz + qw * tz + (qx * ty - qy * tx))


def quat_from_axis_angle(axis, angle):
    h = 0.5 * angle
    s = math.sin(h)
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(h))


def quat_from_rpy(roll, pitch, yaw):
    """URDF rpy: fixed-axis X (roll), then Y (pitch), then Z (yaw): R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr = math.cos(roll * 0.5), math.sin(roll * 0.5)
    cp, sp = math.cos(pitch * 0.5), math.sin(pitch * 0.5)
    cy, sy = math.cos(yaw * 0.5), math.sin(yaw * 0.5)
    return (sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
            cr * cp * cy + sr * sp * sy)


def rpy_from_quat(q):
    x, y, z, w = q
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    s = 2.0 * (w * y - z * x)
    pitch = math.copysign(math.pi / 2.0, s) if abs(s) >= 1.0 else math.asin(s)
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return (roll, pitch, yaw)


def quat_to_matrix(q):
    x, y, z, w = q
    return ((1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
            (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
            (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)))


def quat_from_matrix(m):
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0.0:
        s = math.sqrt(tr + 1.0) * 2.0
        q = ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s)
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2.0
        q = (0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s)
    elif m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2.0
        q = ((m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s)
    else:
        s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2.0
        q = ((m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s)
    return quat_normalize(q)


def pose_mul(a, b):
    """Compose: world_T_b = world_T_a * a_T_b."""
    pa, qa = a
    pb, qb = b
    r = quat_rotate(qa, pb)
    return ((pa[0] + r[0], pa[1] + r[1], pa[2] + r[2]), quat_mul(qa, qb))


def pose_inv(a):
    p, q = a
    qi = quat_conj(q)
    r = quat_rotate(qi, p)
    return ((-r[0], -r[1], -r[2]), qi)


def transform_point(pose, v):
    r = quat_rotate(pose[1], v)
    p = pose[0]
    return (p[0] + r[0], p[1] + r[1], p[2] + r[2])


def to_ode_quat(q):
    return (q[3], q[0], q[1], q[2])


def from_ode_quat(q):
    return (q[1], q[2], q[3], q[0])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(v):
    return math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])


def normalized(v):
    n = norm(v)
    return (v[0] / n, v[1] / n, v[2] / n)


def check_pose(pose, what):
    """Validate and normalise a user pose; raise ValueError naming ``what`` if it is unusable."""
    try:
        p, q = pose
        p = tuple(float(x) for x in p)
        q = tuple(float(x) for x in q)
    except (TypeError, ValueError):
        raise InputError("%s: a pose is ((x, y, z), (qx, qy, qz, qw)), got %r" % (what, pose))
    if len(p) != 3 or len(q) != 4:
        raise InputError("%s: a pose is ((x, y, z), (qx, qy, qz, qw)), got %r" % (what, pose))
    if not all(math.isfinite(x) for x in p + q):
        raise InputError("%s: pose has a non-finite value: %r" % (what, pose))
    if max(abs(x) for x in p) > LENGTH_LIMIT:
        raise InputError("%s: position %r is beyond %g m (limits: docs/simulator.md)"
                         % (what, p, LENGTH_LIMIT))
    try:
        q = quat_normalize(q)
    except ValueError:
        raise InputError("%s: orientation quaternion %r has zero length" % (what, q))
    return (p, q)


def check_vec3(v, what):
    try:
        v = tuple(float(x) for x in v)
    except (TypeError, ValueError):
        raise InputError("%s: expected 3 numbers, got %r" % (what, v))
    if len(v) != 3:
        raise InputError("%s: expected 3 numbers, got %r" % (what, v))
    if not all(math.isfinite(x) for x in v):
        raise InputError("%s: non-finite value in %r" % (what, v))
    return v

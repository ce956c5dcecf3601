"""Seed 000's end-effector-centred camera views (section III-G), pure.

Side view, equations (1)-(7), with the end effector at (x_EE, y_EE, z_EE) in the base frame,
l its horizontal distance from the base and r the camera's distance from the end effector::

    alpha = atan2(y_EE, x_EE)                    (1)
    beta  = atan2(r, l)                          (2)
    d     = sqrt(l^2 + r^2)                      (3)
    x_cam = d cos(alpha + beta)                  (4)
    y_cam = d sin(alpha + beta)                  (5)
    z_cam = z_EE                                 (6)
    roll = -pi/2, pitch = 0, yaw = pi + alpha    (7)

The camera frame is an optical frame (z = viewing axis). With (7) its z axis is horizontal and
perpendicular to the base-to-end-effector line, pointing at the end effector, and its image
x axis stays parallel to the ground. The seed shows top and front views without equations;
ours follow the same rules (xy image plane parallel to the world's or vertical, z axis through
the end effector):

- top:   camera r above the end effector looking down, image up = away from the base
         (position (x_EE, y_EE, z_EE + r), roll = pi, pitch = 0, yaw = alpha - pi/2);
- front: camera r beyond the end effector on the base-to-EE line, looking back at it
         (position ((l + r) cos alpha, (l + r) sin alpha, z_EE), roll = -pi/2, pitch = 0,
         yaw = alpha + pi/2).
"""
import math

VIEWS = ("side", "top", "front")


def side_view(ee, r):
    """((x, y, z), (roll, pitch, yaw)) of the side camera, equations (1)-(7)."""
    x_ee, y_ee, z_ee = ee
    alpha = math.atan2(y_ee, x_ee)                      # (1)
    dist = math.hypot(x_ee, y_ee)                       # l of the seed
    beta = math.atan2(r, dist)                          # (2)
    d = math.sqrt(dist * dist + r * r)                  # (3)
    position = (d * math.cos(alpha + beta),             # (4)
                d * math.sin(alpha + beta),             # (5)
                z_ee)                                   # (6)
    return position, (-math.pi / 2.0, 0.0, math.pi + alpha)   # (7)


def top_view(ee, r):
    x_ee, y_ee, z_ee = ee
    alpha = math.atan2(y_ee, x_ee)
    return (x_ee, y_ee, z_ee + r), (math.pi, 0.0, alpha - math.pi / 2.0)


def front_view(ee, r):
    x_ee, y_ee, z_ee = ee
    alpha = math.atan2(y_ee, x_ee)
    reach = math.hypot(x_ee, y_ee) + r
    return ((reach * math.cos(alpha), reach * math.sin(alpha), z_ee),
            (-math.pi / 2.0, 0.0, alpha + math.pi / 2.0))


def view(name, ee, r):
    """Pose of the named view ("side", "top" or "front")."""
    try:
        fn = {"side": side_view, "top": top_view, "front": front_view}[name]
    except KeyError:
        raise ValueError("unknown end-effector view %r: use one of %s" % (name, ", ".join(VIEWS)))
    return fn(ee, r)


def rotation_matrix(rpy):
    """3x3 rotation (rows) of fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return ((cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
            (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
            (-sp, cp * sr, cp * cr))


def quaternion(rpy):
    """(x, y, z, w) of fixed-axis roll, pitch, yaw."""
    r, p, y = (a / 2.0 for a in rpy)
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)


def to_camera(position, rpy, point):
    """A world point expressed in the camera (optical) frame at ``position``/``rpy``."""
    R = rotation_matrix(rpy)
    d = [point[i] - position[i] for i in range(3)]
    return tuple(sum(R[j][i] * d[j] for j in range(3)) for i in range(3))   # R^T d


def look_at(eye, target, up=(0.0, 0.0, 1.0)):
    """Quaternion (x, y, z, w) of an optical frame at ``eye`` whose z axis points at ``target``
    with image "up" (-y) as close to ``up`` as possible (not for a view straight along ``up``)."""
    z = [target[i] - eye[i] for i in range(3)]
    n = math.sqrt(sum(c * c for c in z))
    z = [c / n for c in z]
    x = [z[1] * up[2] - z[2] * up[1], z[2] * up[0] - z[0] * up[2], z[0] * up[1] - z[1] * up[0]]  # z cross up
    n = math.sqrt(sum(c * c for c in x))
    if n < 1e-9:
        raise ValueError("look_at: the view direction is parallel to up")
    x = [c / n for c in x]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]        # z cross x
    m = ((x[0], y[0], z[0]), (x[1], y[1], z[1]), (x[2], y[2], z[2]))
    return _quat_from_matrix(m)


def _quat_from_matrix(m):
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return ((m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s, 0.25 * s)
    if m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2
        return (0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s)
    if m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2
        return ((m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s)
    s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2
    return ((m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s)

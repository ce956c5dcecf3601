"""Sensor data -> filter measurements (robot_localization's prepare steps), pure.

Poses (odometry pose, PoseWithCovarianceStamped, IMU orientation) are brought into the world
frame; twists (odometry twist, TwistWithCovarianceStamped, IMU angular velocity) and linear
accelerations into base_link; covariances rotated with them. A ``Frame`` is a rigid transform
(rotation matrix ``r``, translation ``t``): ``world_from`` the sensor data's frame for poses,
``base_from`` the sensor's frame for twists and accelerations (identity when the frame is the
filter's own). Per input, ``differential`` turns consecutive poses into a velocity measurement
(in base_link) and ``relative`` measures poses from the first one.

Covariances follow REP-145: a first diagonal element of -1 marks a part as missing (IMU
orientation, angular velocity or acceleration); that part is then not fused.
"""
import math

import numpy as np

from robot_localization import ekf

GRAVITY = 9.80665


class Frame(object):
    __slots__ = ("r", "t")

    def __init__(self, r=None, t=None):
        self.r = np.eye(3) if r is None else np.asarray(r, dtype=float)
        self.t = np.zeros(3) if t is None else np.asarray(t, dtype=float)

    @classmethod
    def from_quaternion(cls, q, t=(0.0, 0.0, 0.0)):
        return cls(matrix_of_quaternion(q), t)

    def is_identity(self):
        return np.allclose(self.r, np.eye(3)) and np.allclose(self.t, 0.0)


IDENTITY = Frame()


def matrix_of_quaternion(q):
    x, y, z, w = q
    n = math.sqrt(x * x + y * y + z * z + w * w)
    if not n > 1e-9 or not math.isfinite(n):
        raise ValueError("quaternion %r has no usable norm" % (tuple(q),))
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def quaternion_of_rpy(roll, pitch, yaw):
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)


def cov6(values, what):
    c = np.asarray(values, dtype=float)
    if c.size != 36 or not np.all(np.isfinite(c)):
        raise ValueError("%s: a covariance needs 36 finite numbers, got %d" % (what, c.size))
    return c.reshape(6, 6)


def cov3(values, what):
    c = np.asarray(values, dtype=float)
    if c.size != 9 or not np.all(np.isfinite(c)):
        raise ValueError("%s: a covariance needs 9 finite numbers, got %d" % (what, c.size))
    return c.reshape(3, 3)


def _rotate_block(c, r):
    return r.dot(c).dot(r.T)


def _blank():
    return np.zeros(ekf.N), np.zeros((ekf.N, ekf.N)), np.zeros(ekf.N, dtype=bool)


class PoseInput(object):
    """The pose part of one input (odomN, poseN, imuN's orientation): its config entries 0..5,
    differential and relative handling."""

    def __init__(self, config, differential=False, relative=False):
        self.mask = np.asarray(config[:6], dtype=bool)
        self.differential, self.relative = differential, relative
        self._first = None           # relative: (rotation, position) of the first pose
        self._last = None            # differential: (rotation, position, covariance, time)

    def measure(self, position, rotation, covariance, time, world_from=IDENTITY):
        """(values, covariance, mask) in state space, or None (nothing to fuse yet)."""
        if not self.mask.any():
            return None
        p = world_from.r.dot(np.asarray(position, dtype=float)) + world_from.t
        r = world_from.r.dot(rotation)
        c = np.array(covariance, dtype=float)
        c[:3, :3] = _rotate_block(c[:3, :3], world_from.r)
        c[3:, 3:] = _rotate_block(c[3:, 3:], world_from.r)
        if self.relative:
            if self._first is None:
                self._first = (r, p)
            r0, p0 = self._first
            p, r = r0.T.dot(p - p0), r0.T.dot(r)
            c[:3, :3] = _rotate_block(c[:3, :3], r0.T)
        values, cov, mask = _blank()
        if not self.differential:
            values[ekf.X:ekf.Z + 1] = p
            values[ekf.ROLL:ekf.YAW + 1] = ekf.rpy_of_matrix(r)
            cov[:6, :6] = c
            mask[:6] = self.mask
            return values, cov, mask
        last, self._last = self._last, (r, p, c, time)
        if last is None or time <= last[3]:
            return None
        r_prev, p_prev, c_prev, t_prev = last
        dt = time - t_prev
        values[ekf.VX:ekf.VZ + 1] = r_prev.T.dot(p - p_prev) / dt
        values[ekf.VROLL:ekf.VYAW + 1] = np.array(ekf.rpy_of_matrix(r_prev.T.dot(r))) / dt
        both = c + c_prev
        both[:3, :3] = _rotate_block(both[:3, :3], r_prev.T)
        cov[6:12, 6:12] = both / (dt * dt)
        mask[6:12] = self.mask
        return values, cov, mask


def twist_measurement(config, linear, angular, covariance, base_from=IDENTITY):
    """Linear and angular velocity of a sensor (in its frame) -> base_link velocities; the lever
    arm of a sensor away from base_link is taken out (v_base = v_sensor - w x offset)."""
    mask6 = np.asarray(config[6:12], dtype=bool)
    if not mask6.any():
        return None
    w = base_from.r.dot(np.asarray(angular, dtype=float))
    o = base_from.t
    lever = (w[1] * o[2] - w[2] * o[1], w[2] * o[0] - w[0] * o[2], w[0] * o[1] - w[1] * o[0])   # w x offset
    v = base_from.r.dot(np.asarray(linear, dtype=float)) - lever
    values, cov, mask = _blank()
    values[ekf.VX:ekf.VZ + 1] = v
    values[ekf.VROLL:ekf.VYAW + 1] = w
    c = np.array(covariance, dtype=float)
    c[:3, :3] = _rotate_block(c[:3, :3], base_from.r)
    c[3:, 3:] = _rotate_block(c[3:, 3:], base_from.r)
    cov[6:12, 6:12] = c
    mask[6:12] = mask6
    return values, cov, mask


def imu_measurements(config, pose_input, orientation, orientation_cov, angular, angular_cov, accel, accel_cov,
                     time, base_from=IDENTITY, remove_gravity=False, gravity=GRAVITY):
    """An Imu message -> a list of (values, covariance, mask): the orientation (as base_link's, in
    the world frame), the angular velocity and the linear acceleration (in base_link), each left
    out when its covariance starts with -1 or its config entries are all false. The orientation
    of an IMU is of the sensor: base_link's is R_sensor * R_base_from^T."""
    out = []
    have_orientation = orientation_cov[0] != -1 and any(abs(v) > 0 for v in orientation)
    r_sensor = matrix_of_quaternion(orientation) if have_orientation else None
    if have_orientation:
        c = np.zeros((6, 6))
        c[3:, 3:] = _rotate_block(cov3(orientation_cov, "imu orientation"), base_from.r)
        got = pose_input.measure(np.zeros(3), r_sensor.dot(base_from.r.T), c, time)
        if got is not None:
            values, cov, mask = got
            mask[:3] = False               # an IMU says nothing of the position
            if mask.any():
                out.append((values, cov, mask))
    if angular_cov[0] != -1:
        c = np.zeros((6, 6))
        c[3:, 3:] = cov3(angular_cov, "imu angular velocity")
        cfg = list(config)
        cfg[6:9] = [False] * 3
        got = twist_measurement(cfg, (0.0, 0.0, 0.0), angular, c, Frame(base_from.r))
        if got is not None:
            out.append(got)
    mask_a = np.asarray(config[12:15], dtype=bool)
    if accel_cov[0] != -1 and mask_a.any():
        a = np.asarray(accel, dtype=float)
        if remove_gravity:
            # the IMU measures gravity as an upward acceleration; without an orientation, level is assumed
            up = np.array([0.0, 0.0, gravity])
            if r_sensor is not None:
                up = r_sensor.T.dot(up)
            a = a - up
        values, cov, mask = _blank()
        values[ekf.AX:ekf.AZ + 1] = base_from.r.dot(a)
        cov[12:, 12:] = _rotate_block(cov3(accel_cov, "imu linear acceleration"), base_from.r)
        mask[12:] = mask_a
        out.append((values, cov, mask))
    return out

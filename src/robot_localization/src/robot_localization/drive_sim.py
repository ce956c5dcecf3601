"""A planar drive and the noisy wheel odometry and IMU a robot would report on it, for tests and
demonstrations of the filter (pure; all randomness from one seeded generator).

The path: speed ramps to ``speed``, then alternates straight stretches and arcs (yaw rate
+-``turn_rate``) until ``length`` metres are driven. Odometry reports the body twist (vx, vyaw)
with white noise, the IMU its yaw (absolute, noisy), yaw rate (noisy, with a constant bias) and
the body acceleration plus gravity (noisy), as a gazebo_ros / hector IMU would.
"""
import math

import numpy as np


class Sample(object):
    __slots__ = ("t", "x", "y", "yaw", "v", "w", "a")

    def __init__(self, t, x, y, yaw, v, w, a):
        self.t, self.x, self.y, self.yaw, self.v, self.w, self.a = t, x, y, yaw, v, w, a


def drive(length=20.0, speed=1.0, turn_rate=0.4, rate=50.0, accel=0.5):
    """The true states at ``rate`` Hz until ``length`` metres are driven (then the robot stops)."""
    dt = 1.0 / rate
    t = x = y = yaw = v = travelled = 0.0
    out = [Sample(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)]
    while travelled < length:
        a = accel if v < speed else 0.0
        remaining = length - travelled
        if remaining < 0.5 * v * v / accel + 1e-9:
            a = -accel
        phase = int(t / 4.0) % 4           # straight, left arc, straight, right arc: 4 s each
        w = (0.0, turn_rate, 0.0, -turn_rate)[phase]
        v_new = max(0.0, min(speed, v + a * dt))
        a = (v_new - v) / dt
        mid_yaw = yaw + 0.5 * w * dt
        step = 0.5 * (v + v_new) * dt
        x += step * math.cos(mid_yaw)
        y += step * math.sin(mid_yaw)
        yaw += w * dt
        v = v_new
        travelled += step
        t += dt
        out.append(Sample(t, x, y, yaw, v, w, a))
        if v == 0.0 and a <= 0.0 and travelled > 0.5 * length:
            break
    return out


class Noise(object):
    def __init__(self, seed=0, odom_v=0.05, odom_w=0.05, imu_yaw=0.01, imu_w=0.005, imu_w_bias=0.002,
                 imu_a=0.05):
        self.rng = np.random.default_rng(seed)
        self.odom_v, self.odom_w = odom_v, odom_w
        self.imu_yaw, self.imu_w, self.imu_w_bias, self.imu_a = imu_yaw, imu_w, imu_w_bias, imu_a

    def odometry(self, s):
        """(vx, vyaw) as wheel odometry reports it."""
        return s.v + self.rng.normal(0.0, self.odom_v), s.w + self.rng.normal(0.0, self.odom_w)

    def imu(self, s, gravity=9.80665):
        """(yaw, yaw rate, (ax, ay, az)) in the IMU (= base) frame, gravity included."""
        return (s.yaw + self.rng.normal(0.0, self.imu_yaw),
                s.w + self.imu_w_bias + self.rng.normal(0.0, self.imu_w),
                (s.a + self.rng.normal(0.0, self.imu_a), s.v * s.w + self.rng.normal(0.0, self.imu_a),
                 gravity + self.rng.normal(0.0, self.imu_a)))

"""Joint waypoints -> a timed, piecewise-linear-with-smoothstep trajectory (pure)."""
import numpy as np


class JointTrajectory(object):
    """Waypoints q_k (rows) reached at times t_k; between them each joint follows a smoothstep
    (zero velocity at every waypoint, so a slow PID tracks it without overshoot)."""

    def __init__(self, joint_names, waypoints, times):
        self.joint_names = list(joint_names)
        self.q = np.asarray(waypoints, dtype=float)
        self.t = np.asarray(times, dtype=float)
        if len(self.q) != len(self.t) or len(self.q) == 0:
            raise ValueError("%d waypoints but %d times" % (len(self.q), len(self.t)))

    @property
    def duration(self):
        return float(self.t[-1])

    def sample(self, t):
        if t <= self.t[0]:
            return self.q[0].copy()
        if t >= self.t[-1]:
            return self.q[-1].copy()
        k = int(np.searchsorted(self.t, t, side="right")) - 1
        span = self.t[k + 1] - self.t[k]
        s = (t - self.t[k]) / span if span > 0 else 1.0
        s = s * s * (3 - 2 * s)
        return self.q[k] + s * (self.q[k + 1] - self.q[k])

    def velocity(self, t):
        """d sample / dt (zero at every waypoint and outside the trajectory)."""
        if t <= self.t[0] or t >= self.t[-1]:
            return np.zeros(self.q.shape[1])
        k = int(np.searchsorted(self.t, t, side="right")) - 1
        span = self.t[k + 1] - self.t[k]
        if span <= 0:
            return np.zeros(self.q.shape[1])
        s = (t - self.t[k]) / span
        return (6.0 * s * (1.0 - s) / span) * (self.q[k + 1] - self.q[k])

    def samples(self, period):
        """[(t, q, qdot)] every ``period`` s from the start to the end (the end included): the
        points of a trajectory_msgs/JointTrajectory whose cubic interpolation follows this one."""
        if self.t[-1] <= self.t[0]:
            return [(float(self.t[0]), self.q[-1].copy(), np.zeros(self.q.shape[1]))]
        n = max(1, int(np.ceil((self.t[-1] - self.t[0]) / period - 1e-9)))
        times = [self.t[0] + min(k * period, self.t[-1] - self.t[0]) for k in range(n + 1)]
        return [(float(t), self.sample(t), self.velocity(t)) for t in times]


def time_waypoints(joint_names, waypoints, max_speed, min_segment=0.05, start_time=0.0):
    """Times for waypoints so that no joint exceeds ``max_speed`` (rad/s, scalar or per joint) on
    average over a segment; smoothstep peaks at 1.5x that."""
    q = np.asarray(waypoints, dtype=float)
    vmax = np.broadcast_to(np.asarray(max_speed, dtype=float), q.shape[1:])
    times = [start_time]
    for k in range(1, len(q)):
        dt = float(np.max(np.abs(q[k] - q[k - 1]) / vmax))
        times.append(times[-1] + max(min_segment, dt))
    return JointTrajectory(joint_names, q, times)

"""Pure pursuit waypoint following for the Polaris (pure; no rospy).

The rear axle centre (base_link_polaris) chases a look-ahead point on the path; the curvature
kappa = 2 sin(alpha) / L_d (alpha: bearing of the look-ahead point, L_d its distance) goes with
the speed to the Ackermann node as cmd_vel (v, v kappa). Progress along the path only moves
forward (nearest waypoint searched in a window ahead), so a closed lap ends where it started.
"""
import math

from polaris_description.errors import ConfigError


class PurePursuit(object):
    def __init__(self, waypoints, lookahead=3.0, speed=1.5, closed=True, window=15, goal_tolerance=1.0):
        pts = [tuple(map(float, p[:2])) for p in waypoints]
        if len(pts) < 2 or not all(math.isfinite(c) for p in pts for c in p):
            raise ConfigError("pure pursuit needs at least 2 finite waypoints, got %d" % len(pts))
        if not (lookahead > 0 and speed > 0):
            raise ConfigError("lookahead and speed must be positive (got %r, %r)" % (lookahead, speed))
        self.path = pts + [pts[0]] if closed else pts
        self.lookahead = float(lookahead)
        self.speed = float(speed)
        self.window = int(window)
        self.goal_tolerance = float(goal_tolerance)
        self.index = 0
        self.done = False

    def _nearest(self, x, y):
        best, best_d = self.index, float("inf")
        for i in range(self.index, min(len(self.path), self.index + self.window)):
            d = math.hypot(self.path[i][0] - x, self.path[i][1] - y)
            if d < best_d:
                best, best_d = i, d
        return best, best_d

    def cross_track(self, x, y):
        """Distance to the nearest path segment (m)."""
        best = float("inf")
        for i in range(len(self.path) - 1):
            (ax, ay), (bx, by) = self.path[i], self.path[i + 1]
            dx, dy = bx - ax, by - ay
            t = max(0.0, min(1.0, ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy or 1.0)))
            best = min(best, math.hypot(ax + t * dx - x, ay + t * dy - y))
        return best

    def update(self, x, y, yaw):
        """(v, omega) for the pose (x, y, yaw) of the rear axle centre; (0, 0) once done."""
        if self.done:
            return 0.0, 0.0
        self.index, _ = self._nearest(x, y)
        last = len(self.path) - 1
        to_goal = math.hypot(self.path[last][0] - x, self.path[last][1] - y)
        if self.index >= last - 1 and to_goal < self.goal_tolerance:
            self.done = True
            return 0.0, 0.0
        target = self.path[last]
        for i in range(self.index, len(self.path)):
            if math.hypot(self.path[i][0] - x, self.path[i][1] - y) >= self.lookahead:
                target = self.path[i]
                break
        dx, dy = target[0] - x, target[1] - y
        ld = math.hypot(dx, dy) or 1e-6
        alpha = math.atan2(dy, dx) - yaw
        kappa = 2.0 * math.sin(alpha) / ld
        v = self.speed
        if self.index >= last - 3:
            v = max(0.3, min(v, math.hypot(self.path[last][0] - x, self.path[last][1] - y)))
        return v, v * kappa

"""Ackermann steering for the Polaris (pure; no rospy).

The seed (section 5.3.2, figure 10) gives, for a turn of radius R whose centre lies to the RIGHT,
the steering angles (magnitudes, left and right wheel), l the track, d the wheelbase::

    alpha_L = pi/2 - atan((R + l/2) / d)        alpha_R = pi/2 - atan((R - l/2) / d)

:func:`seed_angles` is that formula as printed. The vehicle's joints steer positive to the LEFT
(ROS convention), so :func:`steering_angles` works with the signed curvature kappa = 1/R
(positive left, 0 straight) and is the same formula written without the pole at R = inf::

    delta_L = atan(d kappa / (1 - kappa l/2))   delta_R = atan(d kappa / (1 + kappa l/2))

(a right turn of radius R gives delta = -alpha; a test checks the two agree). Straight driving is
the limit kappa -> 0. The rear wheels have no differential; each gets the speed of its own
circle: v_L = v (1 - kappa t/2), v_R = v (1 + kappa t/2), t the rear track, as wheel rates v/r.
"""
import math
from collections import namedtuple

from polaris_description import geometry as G
from polaris_description.errors import CommandError

WheelCommand = namedtuple("WheelCommand", "steer_left steer_right rear_left rear_right curvature clamped")


def seed_angles(radius, track=G.STEER_TRACK, wheelbase=G.WHEELBASE):
    """The seed's formula, verbatim: (alpha_L, alpha_R) for a right turn of radius ``radius`` > l/2."""
    return (math.pi / 2.0 - math.atan((radius + track / 2.0) / wheelbase),
            math.pi / 2.0 - math.atan((radius - track / 2.0) / wheelbase))


def steering_angles(curvature, track=G.STEER_TRACK, wheelbase=G.WHEELBASE):
    """(delta_left, delta_right), positive left, for a signed curvature (1/m, positive left)."""
    k = curvature
    return (math.atan2(wheelbase * k, 1.0 - k * track / 2.0),
            math.atan2(wheelbase * k, 1.0 + k * track / 2.0))


def max_curvature(track=G.STEER_TRACK, wheelbase=G.WHEELBASE, limit=G.STEER_LIMIT):
    """The largest curvature whose inner wheel stays within the steering limit."""
    return 1.0 / (wheelbase / math.tan(limit) + track / 2.0)


def radius_of(delta_left, delta_right, track=G.STEER_TRACK, wheelbase=G.WHEELBASE):
    """Signed distances from the rear axle centre to where each front wheel's axis meets the rear
    axle line (both equal under Ackermann; inf when straight)."""
    out = []
    for delta, y in ((delta_left, track / 2.0), (delta_right, -track / 2.0)):
        if abs(delta) < 1e-12:
            out.append(math.inf)
        else:
            out.append(y + wheelbase / math.tan(delta))
    return tuple(out)


class Ackermann(object):
    """cmd_vel (v, omega) -> per-wheel commands. ``same_angle=True`` reproduces the seed's set-up
    (one steering angle on both wheels, one speed on both rear wheels) as a baseline."""

    def __init__(self, wheelbase=G.WHEELBASE, steer_track=G.STEER_TRACK, rear_track=G.REAR_TRACK,
                 wheel_radius=G.WHEEL_RADIUS, steer_limit=G.STEER_LIMIT, same_angle=False):
        for name, value in (("wheelbase", wheelbase), ("steer_track", steer_track),
                            ("rear_track", rear_track), ("wheel_radius", wheel_radius),
                            ("steer_limit", steer_limit)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise CommandError("Ackermann: %s must be a positive number, got %r" % (name, value))
        self.wheelbase = float(wheelbase)
        self.steer_track = float(steer_track)
        self.rear_track = float(rear_track)
        self.wheel_radius = float(wheel_radius)
        self.steer_limit = float(steer_limit)
        self.same_angle = bool(same_angle)
        self.k_max = (math.tan(steer_limit) / wheelbase if same_angle
                      else max_curvature(steer_track, wheelbase, steer_limit))
        self._last_curvature = 0.0

    def command(self, v, omega):
        """WheelCommand for forward speed ``v`` (m/s) and yaw rate ``omega`` (rad/s). With v == 0
        the wheels stop and the steering keeps its last curvature (a car cannot turn in place).
        Curvatures beyond the steering limit are clamped (``clamped`` True)."""
        for name, value in (("linear.x", v), ("angular.z", omega)):
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise CommandError("cmd_vel %s is %r: send finite numbers" % (name, value))
        clamped = False
        if abs(v) < 1e-6:
            k = self._last_curvature
            v = 0.0
        else:
            k = omega / v
            if abs(k) > self.k_max:
                k = math.copysign(self.k_max, k)
                clamped = True
        self._last_curvature = k
        return self.for_curvature(v, k, clamped)

    def for_curvature(self, v, k, clamped=False):
        if self.same_angle:
            d = math.atan(self.wheelbase * k)
            dl = dr = d
            wl = wr = v / self.wheel_radius
        else:
            dl, dr = steering_angles(k, self.steer_track, self.wheelbase)
            wl = v * (1.0 - k * self.rear_track / 2.0) / self.wheel_radius
            wr = v * (1.0 + k * self.rear_track / 2.0) / self.wheel_radius
        return WheelCommand(dl, dr, wl, wr, k, clamped)

    def front_wheel_rates(self, v, k):
        """Wheel rates of the front wheels (4WD): each rolls at its distance from the turn centre;
        the wheel centres sit 0.1 m outside the pivots along the steered axis."""
        out = []
        for side in (1.0, -1.0):
            # pivot at (wheelbase, side * track/2); centre of the turn at (0, 1/k)
            y = side * (self.steer_track / 2.0 + 0.1)
            dist_factor = math.hypot(self.wheelbase * k, 1.0 - k * y)   # = distance * |k|, signed below
            out.append(v * dist_factor / self.wheel_radius)
        return tuple(out)

"""Angle helpers with the semantics of ROS's ``angles`` package (ros_controllers and
gazebo_ros_control take the shortest way on continuous joints with them). The physics core's
actuators use them; ``modrob_sim.ros_control.angles`` re-exports them."""
import math

TWO_PI = 2.0 * math.pi


def normalize_angle_positive(a):
    """Angle in [0, 2*pi)."""
    return math.fmod(math.fmod(a, TWO_PI) + TWO_PI, TWO_PI)


def normalize_angle(a):
    """Angle in [-pi, pi)."""
    a = normalize_angle_positive(a)
    return a - TWO_PI if a > math.pi else a


def shortest_angular_distance(from_angle, to_angle):
    """Signed shortest rotation taking ``from_angle`` to ``to_angle`` (in [-pi, pi])."""
    return normalize_angle(to_angle - from_angle)


def shortest_angular_distance_with_limits(from_angle, to_angle, lower, upper):
    """Like angles::shortest_angular_distance_with_large_limits: the error towards
    ``to_angle`` for a revolute joint whose travel is [lower, upper]. The target is clamped to
    the limits and the path must stay inside them (a revolute joint cannot wrap)."""
    target = min(max(to_angle, lower), upper)
    return target - from_angle

"""Angle helpers with the semantics of ROS's ``angles`` package, used by ros_controllers and
gazebo_ros_control to take the shortest way on continuous joints (one implementation: the
physics core's, whose actuators follow the same rule)."""
from modrob_sim.physics.angles import (TWO_PI, normalize_angle, normalize_angle_positive,  # noqa: F401
                                       shortest_angular_distance, shortest_angular_distance_with_limits)

"""Bulbs and Slides (seed 000, sections IV-D and V-B): pick a light bulb at the red slide's tip and
release it over the blue slide; the two-robot version hands it over through a cradle.

Pure parts: :mod:`.layout` (the world's numbers), :mod:`.grasp_ik` (side-grasp IK),
:mod:`.planner` (joint waypoints for each phase), :mod:`.trajectory` (timing),
:mod:`.outcome` (is the bulb resting on the blue slide?). ROS layer: :mod:`.ros_robot`
(command a robot through motion_publisher, read its joint states), :mod:`.scenario` (the
pick-and-place on a running simulation), :mod:`.recording` (bag and plots).
"""
from modrob_msgs.errors import ModrobError


class ScenarioError(ModrobError):
    """The pick-and-place cannot go on (no bulb at the tip, IK failed, timeout waiting for a joint)."""

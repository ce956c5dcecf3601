"""Motion interface of the modular robots (seed 000, section IV-F), in three layers:

1. the position controllers ``/modrob<N>/<joint>_position_controller/command`` (std_msgs/Float64),
2. ``motion_publisher``: one ``sensor_msgs/JointState`` on ``/modrob<N>/motion_command`` in,
   one Float64 command per joint out (:mod:`.joint_matching`, :mod:`.controller_map`),
3. ``motion_terminal``: text lines from a terminal (:mod:`.terminal_parser`,
   :mod:`.terminal`) turned into JointState messages for the chosen robot.

The modules here are pure (no rospy); the ROS layer lives in :mod:`.publisher_node` and
:mod:`.terminal_node`, which only wire topics and parameters to these cores.
"""
from modrob_motion.errors import MotionError, ParseError, UnknownJointError  # noqa: F401

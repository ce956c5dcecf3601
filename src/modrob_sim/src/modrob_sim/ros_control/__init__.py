"""The gazebo_ros_control emulation: ros_control's hardware abstraction (DefaultRobotHWSim),
controllers and controller manager as a pure core (no rospy), plus a thin ROS layer
(``plugin.py``, ``ros_*.py``) that the /gazebo node loads as ``libgazebo_ros_control.so``.

Pure modules: angles, params, pid, transmissions, plugin_config, hardware, trajectory, manager,
controllers/*, testing (a tiny joint integrator used as a test plant).
"""

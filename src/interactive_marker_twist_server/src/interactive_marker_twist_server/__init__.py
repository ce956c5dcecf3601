"""interactive_marker_twist_server: drag a marker on the robot in RViz to drive it."""

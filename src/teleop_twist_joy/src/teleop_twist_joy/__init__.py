"""teleop_twist_joy: joystick axes to a Twist while a button is held (ROS's teleop_node)."""

"""joy: a Linux joystick device as sensor_msgs/Joy (ROS's joy_node)."""

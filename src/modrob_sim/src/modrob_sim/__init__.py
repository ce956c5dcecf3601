"""ODE simulator with Gazebo's and ros_control's ROS interfaces; motion interface; Bulbs and Slides."""

"""gazebo_plugins' mobile-robot drives (diff drive, skid steer, planar move, tricycle): pure
cores that drive wheel joints through the physics, and their ROS layer (ros_plugins)."""

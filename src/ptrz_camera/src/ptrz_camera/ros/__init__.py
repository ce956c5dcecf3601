"""ROS layers of ptrz_camera: one class per node."""

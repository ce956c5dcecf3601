"""ptrz_camera: the pan/tilt/roll/zoom camera digital twin of seed 002.

Pure modules (no rospy): ``description`` (xacro -> URDF, camera poses), ``keymap`` (the keyboard
teleop's key table and state), ``scanner`` (the back-and-forth scan), ``zoom`` (field of view,
range), ``pinhole`` and ``kinematics`` (camera geometry), ``tracking`` (segmentation, floor
position, fusion, coverage). ROS layers live in ``ptrz_camera.ros``."""

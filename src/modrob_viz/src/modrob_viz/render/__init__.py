"""Off-screen 3D rendering of camera streams with RViz/OGRE (see docs/cameras.md).

Pure modules (no rospy, no Qt): :mod:`pinhole` (intrinsics, projection, Gazebo's field-of-view
formula), :mod:`ee_views` (seed 000's end-effector-centred views, equations (1)-(7)),
:mod:`camera_spec` (validated camera definitions), :mod:`video` (OpenCV video files).
:mod:`xvfb` starts a private X server; :mod:`rviz_renderer` hosts RViz in this process and grabs
its camera panels; :mod:`node` is the ROS layer of the ``camera_renderer`` node.
"""

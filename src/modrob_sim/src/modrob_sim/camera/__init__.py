"""Cameras in the /gazebo node: the scene publisher (every model's visuals as a MarkerArray in
per-link tf frames, and those frames) and the ``libgazebo_ros_camera.so`` sensor plugin. Images
are drawn by the separate ``modrob_viz camera_renderer`` process (docs/cameras.md)."""

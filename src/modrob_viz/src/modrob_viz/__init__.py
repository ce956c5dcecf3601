"""Trajectory recording and visualisation (tf2, rosbag, KDL), markers, image streams and user tests."""

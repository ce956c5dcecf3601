"""ROS web_video_server's HTTP interface in Python: MJPEG streams and JPEG snapshots of image topics."""

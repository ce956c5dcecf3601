"""Messages shared by the modrob packages; conversions between them and common ROS types."""

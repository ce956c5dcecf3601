"""Module orders to Gazebo-ready URDF, controller YAML and launch files."""

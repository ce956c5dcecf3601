"""ROS\x27s kdl_parser_py: ``from kdl_parser_py.urdf import treeFromString`` and friends."""

"""Kinematics from URDF for every package of the workspace: URDF -> KDL tree with the bookkeeping
Debian's PyKDL bindings do not expose, tree forward kinematics, chain FK and IK within joint
limits (:mod:`modrob_kinematics.kdl_urdf`). Pure: no rospy. ``kdl_parser_py`` offers ROS's API
(``treeFromString`` ...) on top of it."""

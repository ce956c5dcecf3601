"""The thin ROS layer of modrob_viz: one class per node, wiring topics, tf2 and parameters to the
pure modules of the package. The executables in ``scripts/`` build these and spin."""

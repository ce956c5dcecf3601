"""The ROS side of the modrob simulator: the /gazebo node (Gazebo's ROS interface on top of
modrob_sim.physics), its plugin registry and the spawn_model command line.

Pure modules (no rospy): plugins, transforms, description, world_file, sim_loop.
ROS layer: server (the node), spawn_model (the script's logic), markers.
"""

"""franka_ros' simulated hardware (franka_gazebo) for modrob_sim: the FrankaHWSim robotSimType,
the FrankaGripperSim gripper and the FrankaStateController, as Python types of the ros_control
emulation. Pure modules: hw_sim, gripper, state_controller; ROS side: ros_types."""

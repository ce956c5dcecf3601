"""robot_localization: ekf_localization_node (an EKF over odometry, IMU, twist and pose inputs) with
ROS's names, parameters and topics, as a workspace package."""

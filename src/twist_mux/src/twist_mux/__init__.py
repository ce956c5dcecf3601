"""twist_mux: ROS's twist multiplexer (priorities, timeouts, locks) as a workspace package."""

"""rqt_plot for a machine without rqt: live plots of numeric message fields
(``/topic/field[index]``) over a rolling window of ROS (simulated) time, saved to PNG/CSV."""

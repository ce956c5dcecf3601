"""Polaris Ranger EV e-ATV: steering, drive, odometry, IMU, GPS, lidar (seed 003)."""

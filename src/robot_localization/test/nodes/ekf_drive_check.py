#!/usr/bin/env python3
"""rostest node for ekf_localization.test: publishes the drive of robot_localization.drive_sim (20 m
at 2 m/s) as noisy nav_msgs/Odometry on /odom and sensor_msgs/Imu on /imu/data at 50 Hz of wall
time, and compares /odometry/filtered with the true pose at each message's stamp."""
import bisect
import math
import threading
import time
import unittest

import rospy
import rostest
import tf2_ros
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu

from modrob_sim.waits import wait_until

from robot_localization import drive_sim
from robot_localization.measurements import quaternion_of_rpy


class EkfDrive(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("ekf_drive_check")
        cls.lock = threading.Lock()
        cls.filtered = []
        rospy.Subscriber("odometry/filtered", Odometry, cls._on_filtered, queue_size=100)
        cls.odom_pub = rospy.Publisher("odom", Odometry, queue_size=10)
        cls.imu_pub = rospy.Publisher("imu/data", Imu, queue_size=10)
        cls.tf = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf)
        for p in (cls.odom_pub, cls.imu_pub):
            wait_until(lambda: p.get_num_connections() > 0, 30,
                       "the filter subscribing to %s" % p.resolved_name)

    @classmethod
    def _on_filtered(cls, msg):
        with cls.lock:
            cls.filtered.append(msg)

    def publish_drive(self):
        """Publishes the drive in wall time; returns the truth as (stamps, samples)."""
        path = drive_sim.drive(20.0, speed=2.0, turn_rate=0.8, accel=1.0)
        noise = drive_sim.Noise(seed=3)
        t0 = rospy.Time.now().to_sec() + 0.1
        stamps = []
        for s in path:
            delay = t0 + s.t - rospy.Time.now().to_sec()
            if delay > 0:
                time.sleep(delay)                      # the sensors' 50 Hz
            stamp = rospy.Time.from_sec(t0 + s.t)
            stamps.append(stamp.to_sec())
            v, w = noise.odometry(s)
            odom = Odometry()
            odom.header.stamp, odom.header.frame_id, odom.child_frame_id = stamp, "odom", "base_link"
            odom.twist.twist.linear.x, odom.twist.twist.angular.z = v, w
            odom.twist.covariance = [0.0025 if i % 7 == 0 else 0.0 for i in range(36)]
            odom.pose.covariance = [1e6 if i % 7 == 0 else 0.0 for i in range(36)]
            self.odom_pub.publish(odom)
            yaw, rate, acc = noise.imu(s)
            imu = Imu()
            imu.header.stamp, imu.header.frame_id = stamp, "base_link"
            (imu.orientation.x, imu.orientation.y, imu.orientation.z,
             imu.orientation.w) = quaternion_of_rpy(0.0, 0.0, yaw)
            imu.orientation_covariance = [1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-4]
            imu.angular_velocity.z = rate
            imu.angular_velocity_covariance = [2.5e-5, 0, 0, 0, 2.5e-5, 0, 0, 0, 2.5e-5]
            imu.linear_acceleration.x, imu.linear_acceleration.y, imu.linear_acceleration.z = acc
            imu.linear_acceleration_covariance = [0.0025, 0, 0, 0, 0.0025, 0, 0, 0, 0.0025]
            self.imu_pub.publish(imu)
        return stamps, path

    def test_filtered_odometry_follows_the_drive(self):
        stamps, path = self.publish_drive()
        end = stamps[-1]
        wait_until(lambda: self.filtered and self.filtered[-1].header.stamp.to_sec() >= end - 0.05, 10,
                   "the filter's output after the drive")
        with self.lock:
            out = [m for m in self.filtered if stamps[0] <= m.header.stamp.to_sec() <= end]
        # output all along the drive (50 Hz when the node has a core; a loaded machine slows its timer)
        gaps = [b.header.stamp.to_sec() - a.header.stamp.to_sec() for a, b in zip(out, out[1:])]
        self.assertGreater(len(out), 2 * (end - stamps[0]))
        self.assertLess(max(gaps), 1.0)
        m = out[-1]
        self.assertEqual((m.header.frame_id, m.child_frame_id), ("odom", "base_link"))
        errors = []
        for msg in out:
            t = msg.header.stamp.to_sec()
            k = min(max(bisect.bisect_left(stamps, t), 1), len(stamps) - 1)
            a, b = path[k - 1], path[k]
            f = (t - stamps[k - 1]) / (stamps[k] - stamps[k - 1])
            x, y = a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)
            p = msg.pose.pose.position
            errors.append(math.hypot(p.x - x, p.y - y))
        rospy.loginfo("ekf_drive: largest error %.4f m over %d estimates" % (max(errors), len(errors)))
        self.assertLess(max(errors), 0.05, "largest error %.3f m" % max(errors))
        tf = self.tf.lookup_transform("odom", "base_link", rospy.Time(0), rospy.Duration(2.0))
        self.assertAlmostEqual(tf.transform.translation.x, path[-1].x, delta=0.05)
        self.assertAlmostEqual(tf.transform.translation.y, path[-1].y, delta=0.05)


if __name__ == "__main__":
    rostest.rosrun("robot_localization", "ekf_drive_check", EkfDrive)

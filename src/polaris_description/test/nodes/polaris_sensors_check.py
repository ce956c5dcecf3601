#!/usr/bin/env python3
"""Checks for polaris_sensors.test (see there)."""
import math
import threading
import unittest

import numpy as np
import rospy
import rostest
from gazebo_msgs.msg import ModelStates
from geometry_msgs.msg import Vector3Stamped
from sensor_msgs.msg import Imu, NavSatFix, PointCloud2

from modrob_sim.waits import controller_states, sim_sleep, wait_until
from polaris_description import gps, parking_lot
from polaris_description.cloud import xyz_from_cloud
from polaris_description.obstacle import LIDAR_OFFSET
from polaris_description.transforms import rotate


class PolarisSensors(unittest.TestCase):
    def model_pose(self):
        ms = rospy.wait_for_message("/gazebo/model_states", ModelStates, timeout=120)
        p = ms.pose[ms.name.index("polaris")]
        return ((p.position.x, p.position.y, p.position.z),
                (p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w))

    def wait_at_rest(self, still=0.2, timeout=120.0):
        """Wait until the vehicle has settled on its suspension after the spawn: its twist in
        /gazebo/model_states below 5 mm/s and 0.01 rad/s for ``still`` simulated seconds."""
        since = [None]
        rested = threading.Event()

        def on_states(ms):
            if "polaris" not in ms.name:
                return
            tw = ms.twist[ms.name.index("polaris")]
            v = math.sqrt(tw.linear.x ** 2 + tw.linear.y ** 2 + tw.linear.z ** 2)
            w = math.sqrt(tw.angular.x ** 2 + tw.angular.y ** 2 + tw.angular.z ** 2)
            now = rospy.Time.now()
            if v > 0.005 or w > 0.01:
                since[0] = None
            elif since[0] is None:
                since[0] = now
            elif (now - since[0]).to_sec() >= still:
                rested.set()

        sub = rospy.Subscriber("/gazebo/model_states", ModelStates, on_states, queue_size=1)
        try:
            self.assertTrue(rested.wait(timeout), "the vehicle did not come to rest within %.0f s" % timeout)
        finally:
            sub.unregister()

    def wait_for_controllers(self, count=5, timeout=120.0):
        """Wait until the spawner has started the steering and wheel controllers: each moves the
        vehicle a little as it takes hold, which the IMU reads."""
        running = []

        def started():
            running[:] = [n for n, state in controller_states("/", timeout).items() if state == "running"]
            return len(running) >= count
        if not wait_until(started, timeout, period=0.1):
            self.fail("%d controllers running after %.0f s, expected %d: %s"
                      % (len(running), timeout, count, running))

    def test_1_imu_reads_gravity_at_100_hz(self):
        self.wait_for_controllers()
        self.wait_at_rest()
        msgs = []
        sub = rospy.Subscriber("/imu", Imu, msgs.append)
        rospy.wait_for_message("/imu", Imu, timeout=120)
        sim_sleep(2.0)
        sub.unregister()
        # 100 Hz of simulated time: every gap a whole number of 10 ms periods, most of them one (a
        # subscriber that waits for the CPU loses messages from the publisher's queue of 10: a
        # count over the window called that a slower rate)
        stamps = [m.header.stamp.to_sec() for m in msgs]
        gaps = [(b - a) / 0.01 for a, b in zip(stamps, stamps[1:])]
        periods = [max(1, round(g)) for g in gaps]
        self.assertTrue(len(gaps) > 50 and all(abs(g - k) < 0.05 for g, k in zip(gaps, periods)),
                        "/imu not on a 100 Hz grid of simulated time: gaps %s periods" % gaps)
        self.assertGreater(periods.count(1), len(periods) / 2, "/imu mostly slower than 100 Hz: %s" % gaps)
        a = np.array([[m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z]
                      for m in msgs])
        self.assertAlmostEqual(float(np.mean(a[:, 2])), 9.81, delta=0.1)
        self.assertLess(float(np.max(np.abs(np.mean(a[:, :2], axis=0)))), 0.1)

    def test_4_imu_logger_writes_csv_and_tf_has_the_wheels(self):
        import tf2_ros
        from polaris_description.imu_log import read_rows
        path = rospy.get_param("~imu_csv")
        end = rospy.Time.now() + rospy.Duration(30.0)
        rows = []
        while rospy.Time.now() < end and len(rows) < 50:
            rospy.sleep(0.5)
            try:
                rows = read_rows(path)
            except (OSError, ValueError):
                rows = []
        self.assertGreaterEqual(len(rows), 50, "the IMU logger wrote %d rows to %s" % (len(rows), path))
        self.assertAlmostEqual(rows[-1]["linear_acceleration_z"], 9.81, delta=0.2)
        buf = tf2_ros.Buffer()
        self.listener = tf2_ros.TransformListener(buf)
        buf.lookup_transform("base_link_polaris", "polaris_ranger_ev__front_left_wheel", rospy.Time(0),
                             rospy.Duration(30.0))

    def test_2_fix_converts_back_to_the_true_position(self):
        fix = rospy.wait_for_message("/fix", NavSatFix, timeout=120)
        rospy.wait_for_message("/fix_velocity", Vector3Stamped, timeout=30)
        (x, y, z), _ = self.model_pose()
        gx, gy, gz = gps.from_fix(fix.latitude, fix.longitude, fix.altitude)
        self.assertLess(math.hypot(gx - x, gy - y), 0.01,
                        "fix (%.3f, %.3f) vs true (%.3f, %.3f)" % (gx, gy, x, y))
        self.assertAlmostEqual(gz, z, delta=0.01)

    def test_3_cones_appear_on_their_true_surfaces(self):
        cloud = rospy.wait_for_message("/velodyne_points2", PointCloud2, timeout=120)
        (bx, by, bz), q = self.model_pose()
        pts = xyz_from_cloud(cloud) + np.asarray(LIDAR_OFFSET)
        world = np.array([rotate(q, tuple(p)) for p in pts]) + np.array([bx, by, bz])
        seen = 0
        for cone in parking_lot.CONES:
            d = np.hypot(world[:, 0] - cone.x, world[:, 1] - cone.y)
            near = world[(d < 0.5) & (world[:, 2] > 0.035)]
            if math.hypot(cone.x - bx, cone.y - by) < 10.0:
                self.assertGreaterEqual(len(near), 3, "%s at (%.1f, %.1f) not in the cloud"
                                        % (cone.name, cone.x, cone.y))
            for p in near:
                radius = [r for r, z0, z1 in parking_lot.CONE_STACK if z0 - 1e-3 <= p[2] <= z1 + 1e-3]
                if not radius:
                    continue
                err = abs(math.hypot(p[0] - cone.x, p[1] - cone.y) - radius[0])
                self.assertLess(err, 0.05, "%s: a point %.3f m off its surface" % (cone.name, err))
            seen += len(near) > 0
        self.assertGreaterEqual(seen, 2)


if __name__ == "__main__":
    rospy.init_node("polaris_sensors_check")
    rostest.rosrun("polaris_description", "polaris_sensors", PolarisSensors)

"""Waypoint follower node (thin ROS layer): pure pursuit on /odom -> cmd_vel, stopping for an
obstacle found in /velodyne_points2 on the way. The default waypoints are the parking lot's lap
from the spawn point."""
import math
import threading

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import String

from polaris_description import parking_lot
from polaris_description.cloud import xyz_from_cloud
from polaris_description.errors import PolarisError
from polaris_description.obstacle import ObstacleDetector, StopGuard
from polaris_description.pure_pursuit import PurePursuit
from polaris_description.transforms import yaw_pitch_roll


def default_waypoints():
    wps = parking_lot.lap_waypoints(1.0)
    return [(0.0, 0.0)] + wps + [wps[0]]


class LapNode(object):
    def __init__(self, waypoints, speed=1.5, lookahead=3.0, stop_distance=4.0, use_lidar=True, rate=20.0):
        self.pp = PurePursuit(waypoints, lookahead=lookahead, speed=speed, closed=False)
        self.detector = ObstacleDetector()
        self.guard = StopGuard(stop_distance)
        self.use_lidar = use_lidar
        self.lock = threading.Lock()
        self.pose = None
        self.speed = 0.0
        self.cloud = None
        self.kappa = 0.0
        self.state = "waiting for /odom"
        self.max_cross_track = 0.0
        self.cmd = rospy.Publisher("cmd_vel", Twist, queue_size=1)
        self.status = rospy.Publisher("~status", String, queue_size=1, latch=True)
        rospy.Subscriber("odom", Odometry, self.on_odom, queue_size=1)
        if use_lidar:
            rospy.Subscriber("/velodyne_points2", PointCloud2, self.on_cloud, queue_size=1, buff_size=2 ** 22)
        self.timer = rospy.Timer(rospy.Duration(1.0 / rate), self.tick, reset=True)

    def on_odom(self, m):
        p, q = m.pose.pose.position, m.pose.pose.orientation
        with self.lock:
            self.pose = (p.x, p.y, yaw_pitch_roll((q.x, q.y, q.z, q.w))[0])
            self.speed = math.hypot(m.twist.twist.linear.x, m.twist.twist.linear.y)

    def on_cloud(self, m):
        with self.lock:
            self.cloud = m

    def tick(self, _event):
        with self.lock:
            pose, cloud, self.cloud = self.pose, self.cloud, None
        if pose is None:
            return
        if cloud is not None:
            try:
                d = self.detector.distance(xyz_from_cloud(cloud), self.kappa)
            except PolarisError as e:
                rospy.logwarn_throttle(5.0, "lap: %s" % e)
                d = math.inf
            was = self.guard.stopped
            if self.guard.update(d) and not was:
                rospy.loginfo("lap: obstacle %.2f m ahead of the bumper (the car at (%.2f, %.2f)): stopping"
                              % (d, pose[0], pose[1]))
        if self.guard.stopped:
            v, w = 0.0, 0.0
            self.state = "stopped for an obstacle"
        else:
            v, w = self.pp.update(*pose)
            if self.pp.index > 3:
                self.max_cross_track = max(self.max_cross_track, self.pp.cross_track(pose[0], pose[1]))
            self.state = "lap completed" if self.pp.done else "driving (waypoint %d/%d)" % (
                self.pp.index, len(self.pp.path))
            self.kappa = w / v if v > 1e-6 else self.kappa
        msg = Twist()
        msg.linear.x, msg.angular.z = v, w
        self.cmd.publish(msg)
        self.status.publish(String(self.state))


def main():
    rospy.init_node("polaris_lap")
    LapNode(rospy.get_param("~waypoints", None) or default_waypoints(), float(rospy.get_param("~speed", 1.5)),
            float(rospy.get_param("~lookahead", 3.0)), float(rospy.get_param("~stop_distance", 4.0)),
            bool(rospy.get_param("~use_lidar", True)))
    rospy.spin()

#!/usr/bin/env python3
"""rostest node: KDL forward kinematics of a generated URDF (modrob_kinematics.kdl_urdf) agrees with the tf
that robot_state_publisher computes from the same URDF, within 1 mm, for random joint angles.

~namespace: the robot's namespace (its robot_description and joint_states live there)
~tips: links to check (world -> tip)
"""
import random
import unittest

import rospy
import rostest
import tf2_ros
from sensor_msgs.msg import JointState

from modrob_kinematics.kdl_urdf import KinematicChain, tree_from_urdf_string

TOLERANCE = 0.001


class KdlFkVsTf(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        ns = rospy.get_param("~namespace", "/modrob0")
        cls.tips = rospy.get_param("~tips")
        cls.urdf = rospy.get_param(ns + "/robot_description")
        cls.tree = tree_from_urdf_string(cls.urdf)
        cls.buffer = tf2_ros.Buffer()
        cls.listener = tf2_ros.TransformListener(cls.buffer)
        cls.pub = rospy.Publisher(ns + "/joint_states", JointState, queue_size=1)

    def lookup_after(self, names, q, tip, start, timeout=20.0):
        deadline = rospy.Time.now() + rospy.Duration(timeout)
        rate = rospy.Rate(20)
        while not rospy.is_shutdown() and rospy.Time.now() < deadline:
            msg = JointState(name=names, position=q)
            msg.header.stamp = rospy.Time.now()
            self.pub.publish(msg)
            try:
                t = self.buffer.lookup_transform("world", tip, rospy.Time(0))
                if t.header.stamp >= start:
                    return t.transform
            except (tf2_ros.LookupException, tf2_ros.ExtrapolationException,
                    tf2_ros.ConnectivityException):
                pass
            rate.sleep()
        self.fail("no world -> %s transform from robot_state_publisher within %.0f s" % (tip, timeout))

    def test_fk_matches_tf(self):
        rng = random.Random(42)
        names = list(self.tree.joint_names)
        self.assertGreaterEqual(len(names), 3)
        for trial in range(4):
            q = [rng.uniform(*self.tree.limits[n]) for n in names]
            q_by_name = dict(zip(names, q))
            start = rospy.Time.now()
            for tip in self.tips:
                chain = KinematicChain(self.tree, "world", tip)
                frame = chain.fk([q_by_name[n] for n in chain.joint_names])
                t = self.lookup_after(names, q, tip, start)
                got = (t.translation.x, t.translation.y, t.translation.z)
                for axis in range(3):
                    self.assertAlmostEqual(frame.p[axis], got[axis], delta=TOLERANCE,
                                           msg="%s axis %d, trial %d, q=%s" % (tip, axis, trial, q))
                qx, qy, qz, qw = frame.M.GetQuaternion()
                r = t.rotation
                dot = abs(qx * r.x + qy * r.y + qz * r.z + qw * r.w)
                self.assertGreater(dot, 1.0 - 1e-6, "%s orientation, trial %d" % (tip, trial))


if __name__ == "__main__":
    rospy.init_node("kdl_fk_vs_tf")
    rostest.rosrun("modrob_build", "kdl_fk_vs_tf", KdlFkVsTf)

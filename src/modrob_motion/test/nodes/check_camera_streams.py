#!/usr/bin/env python3
"""rostest: the seed's image streams on a robot spawned from a file (no robot_description)."""
import os
import time
import unittest

import cv2
import numpy as np
import rospkg
import rospy
import rostest
import tf2_ros
from gazebo_msgs.srv import SetModelConfiguration
from sensor_msgs.msg import Image
from visualization_msgs.msg import Marker

PRINCIPAL = ("topView", "frontView", "rightView", "orthoView")
EE_VIEWS = ("ee_side", "ee_top", "ee_front")
JOINTS = ["joint%d" % i for i in range(1, 7)]
POSES = ([0.6, 0.7, -0.9, 0.0, 0.6, 0.0], [-1.2, 0.4, 0.5, 0.3, -0.7, 0.5], [2.4, -0.5, 1.1, -0.4, 0.4, 0.0])
W, H = 640, 360


# with the outputs of the other tests: $ROS_HOME (~/.ros by default), a run's own under run_tests.py
OUT = os.path.join(rospkg.get_ros_home(), "test_output", "camera_streams")


def save(msg, name):
    """Keep every checked image for a human to look at."""
    os.makedirs(OUT, exist_ok=True)
    cv2.imwrite(os.path.join(OUT, name + ".png"), pixels(msg)[:, :, ::-1].astype(np.uint8))


def pixels(msg):
    return np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)


def blue_count(msg):
    a = pixels(msg)
    return int(np.count_nonzero((a[..., 2] > 150) & (a[..., 0] < 70) & (a[..., 1] < 70)))


def magenta_centre(msg):
    a = pixels(msg)
    mask = (a[..., 0] > 150) & (a[..., 2] > 150) & (a[..., 1] < 80)
    ys, xs = np.nonzero(mask)
    if len(xs) < 20:
        return None
    return float(xs.mean()), float(ys.mean()), len(xs)


def fresh_image(topic, after, timeout=40.0, predicate=lambda m: True):
    """The first image on ``topic`` stamped after ``after`` (sim time) that satisfies ``predicate``
    (or the last one seen when none does in time)."""
    end = time.monotonic() + timeout
    last = None
    while time.monotonic() < end and not rospy.is_shutdown():
        try:
            msg = rospy.wait_for_message(topic, Image, timeout=10.0)
        except rospy.ROSException:
            continue
        if msg.header.stamp > after:
            last = msg
            if predicate(msg):
                return msg
    return last


class CameraStreams(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.buffer = tf2_ros.Buffer()
        cls.listener = tf2_ros.TransformListener(cls.buffer)
        cls.marker_pub = rospy.Publisher("/camera_test/marker", Marker, queue_size=1, latch=True)
        m = Marker()
        m.header.frame_id = "test_ee_point"
        m.type, m.action, m.frame_locked = Marker.SPHERE, Marker.ADD, True
        m.scale.x = m.scale.y = m.scale.z = 0.05
        m.color.r, m.color.g, m.color.b, m.color.a = 1.0, 0.0, 1.0, 1.0
        m.pose.orientation.w = 1.0
        cls.marker_pub.publish(m)
        rospy.wait_for_service("/gazebo/set_model_configuration", 60.0)
        cls.set_config = rospy.ServiceProxy("/gazebo/set_model_configuration", SetModelConfiguration)

    def _pose(self, q):
        end = time.monotonic() + 60
        while time.monotonic() < end:
            try:
                if self.set_config("modrob0", "", JOINTS, q).success:
                    return rospy.Time.now()
            except rospy.ServiceException:
                pass
            time.sleep(0.5)
        self.fail("set_model_configuration of modrob0 failed (was it spawned?)")

    def test_1_principal_views_see_the_robot_without_robot_description(self):
        self.assertFalse(rospy.has_param("/robot_description")
                         or rospy.has_param("/modrob0/robot_description"))
        t = self._pose(POSES[0])
        for view in PRINCIPAL:   # two renderers start at once: the first images can take a while
            msg = fresh_image("/camera_%s/image" % view, t, 150.0)
            self.assertIsNotNone(msg, "no image from the %s camera" % view)
            self.assertEqual((msg.width, msg.height), (W, H))
            save(msg, view)
            n = blue_count(msg)
            rospy.loginfo("%s: %d blue (robot joint) pixels", view, n)
            self.assertGreater(n, 150, "the %s view does not show the robot's blue joints (%d px)"
                               % (view, n))

    def test_2_end_effector_centred_views_centre_the_end_effector(self):
        def centred(m):
            c = magenta_centre(m)
            return c is not None and abs(c[0] - W / 2.0) < 5.0 and abs(c[1] - H / 2.0) < 5.0
        for q in POSES:
            t = self._pose(q)
            for view in EE_VIEWS:
                # the view follows the jump with the next scene and tf updates: the first image
                # after the pose that shows the end effector centred (else the last one, judged below)
                msg = fresh_image("/camera_%s/image" % view, t, 40.0, centred)
                self.assertIsNotNone(msg, "no image from the %s camera" % view)
                save(msg, "%s_pose%d" % (view, POSES.index(q)))
                c = magenta_centre(msg)
                self.assertIsNotNone(c, "pose %s: the end effector is not visible in the %s view" % (q, view))
                rospy.loginfo("pose %s %s: end effector at (%.1f, %.1f), %d px", q, view, c[0], c[1], c[2])
                self.assertLess(abs(c[0] - W / 2.0), 5.0, "pose %s %s: u = %.1f" % (q, view, c[0]))
                self.assertLess(abs(c[1] - H / 2.0), 5.0, "pose %s %s: v = %.1f" % (q, view, c[1]))


if __name__ == "__main__":
    rospy.init_node("check_camera_streams")
    rostest.rosrun("modrob_motion", "check_camera_streams", CameraStreams)

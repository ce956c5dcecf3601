#!/usr/bin/env python3
"""rostest: an image is consistent with its stamp. A camera at the origin pans back and forth at
a constant speed (tf, 100 Hz) in front of a fixed red sphere; from each image the sphere's world
bearing is estimated with the camera pose at the image's stamp. If the renderer drew from another
time than the stamp, the estimate would lead or lag by speed x delay: opposite for the two pan
directions. The estimate must not depend on the direction of motion (nor err much at all)."""
import math
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import Image
from visualization_msgs.msg import Marker, MarkerArray

W, H, HFOV = 320, 240, 1.0
FX = W / (2.0 * math.tan(HFOV / 2.0))
CX = (W + 1.0) / 2.0
AMPLITUDE = 0.3      # rad: the pan goes -A .. +A
SPEED = 0.8          # rad/s
TARGET = (4.0, 0.0, 0.0)


def pan_at(t):
    """Triangle wave of slope +-SPEED between -A and +A; (angle, direction)."""
    period = 4.0 * AMPLITUDE / SPEED
    s = (t % period) / period
    if s < 0.5:
        return -AMPLITUDE + 4.0 * AMPLITUDE * s, 1
    return 3.0 * AMPLITUDE - 4.0 * AMPLITUDE * s, -1


def quaternion(m):
    w = math.sqrt(max(0.0, 1.0 + m[0, 0] + m[1, 1] + m[2, 2])) / 2.0
    return ((m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w), (m[1, 0] - m[0, 1]) / (4 * w), w)


def optical(yaw):
    """World rotation of an optical frame (z forward, x right, y down) looking horizontally at yaw."""
    c, s = math.cos(yaw), math.sin(yaw)
    rz = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    opt = np.array([[0, 0, 1], [-1, 0, 0], [0, -1, 0]], dtype=float)
    return rz.dot(opt)


class RenderTiming(unittest.TestCase):
    def setUp(self):
        self.t0 = rospy.get_time()
        self.samples = []
        self.lock = threading.Lock()
        self.br = tf2_ros.TransformBroadcaster()
        self.markers = rospy.Publisher("/gazebo/scene_markers", MarkerArray, queue_size=1, latch=True)
        mk = Marker()
        mk.header.frame_id = "world"
        mk.ns, mk.id, mk.type, mk.action = "target", 0, Marker.SPHERE, Marker.ADD
        mk.pose.position.x, mk.pose.position.y, mk.pose.position.z = TARGET
        mk.pose.orientation.w = 1.0
        mk.scale.x = mk.scale.y = mk.scale.z = 0.6
        mk.color.r, mk.color.a = 1.0, 1.0
        self.markers.publish(MarkerArray(markers=[mk]))
        rospy.Subscriber("/pan_cam/image", Image, self.on_image, queue_size=5)

    def broadcast(self):
        t = rospy.Time.now()
        yaw, _ = pan_at(t.to_sec() - self.t0)
        msg = TransformStamped()
        msg.header.stamp, msg.header.frame_id, msg.child_frame_id = t, "world", "pan_cam"
        q = quaternion(optical(yaw))
        (msg.transform.rotation.x, msg.transform.rotation.y, msg.transform.rotation.z,
         msg.transform.rotation.w) = q
        self.br.sendTransform(msg)

    def on_image(self, msg):
        a = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
        mask = (a[..., 0] > 120) & (a[..., 1] < 60) & (a[..., 2] < 60)
        ys, xs = np.nonzero(mask)
        if len(xs) < 50 or xs.min() == 0 or xs.max() == msg.width - 1:
            return                          # not (wholly) in view
        t = msg.header.stamp.to_sec() - self.t0
        yaw, direction = pan_at(t)
        period = 4.0 * AMPLITUDE / SPEED
        if min(t % (period / 2.0), period / 2.0 - t % (period / 2.0)) < 0.1:
            return                          # at a turn: the speed is not constant there
        bearing = yaw + math.atan((CX - (xs.mean() + 0.5)) / FX)
        with self.lock:
            self.samples.append((direction, bearing, float(ys.mean())))

    def test_pose_of_the_stamp(self):
        end = time.monotonic() + 60.0
        while time.monotonic() < end and not rospy.is_shutdown():
            self.broadcast()
            with self.lock:
                n = [sum(1 for s in self.samples if s[0] == d) for d in (1, -1)]
            if min(n) >= 25:
                break
            rospy.rostime.wallsleep(0.01)
        with self.lock:
            samples = list(self.samples)
        self.assertGreaterEqual(min(n), 25, "images with the sphere per direction: %s" % n)
        fwd = np.array([s[1] for s in samples if s[0] == 1])
        back = np.array([s[1] for s in samples if s[0] == -1])
        rospy.loginfo("bearing error: +%.2f rad/s mean %.4f rad (max %.4f), -%.2f rad/s mean %.4f (max %.4f)",
                      SPEED, fwd.mean(), np.abs(fwd).max(), SPEED, back.mean(), np.abs(back).max())
        # a delay d between the pose drawn and the stamp shifts the two directions by 2 x SPEED x d
        self.assertLess(abs(fwd.mean() - back.mean()), 0.006,
                        "the estimate depends on the pan direction: the image is not drawn from the "
                        "pose of its stamp (%.4f vs %.4f rad, delay ~%.0f ms)"
                        % (fwd.mean(), back.mean(), 1000 * abs(fwd.mean() - back.mean()) / (2 * SPEED)))
        self.assertLess(np.abs(np.concatenate([fwd, back])).max(), 0.015)


if __name__ == "__main__":
    rospy.init_node("check_render_timing")
    rostest.rosrun("modrob_viz", "render_timing", RenderTiming)

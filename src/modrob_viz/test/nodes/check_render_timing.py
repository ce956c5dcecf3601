#!/usr/bin/env python3
"""rostest: an image is the view of the scene at its stamp.

1. The camera moves: a camera at the origin pans back and forth at a constant speed (tf, 100 Hz)
   in front of a fixed red sphere; from each image the sphere's world bearing is estimated with
   the camera pose at the image's stamp.
2. The scene moves: a green sphere frame-locked to a tf frame ``mover`` (30 Hz, as the
   simulator's scene) slides sideways back and forth in front of the camera (its tf at 100 Hz,
   so the camera's newest tf is newer than the scene's); its position is estimated from each
   image and compared with where it was at the image's stamp.
If the renderer drew the camera or the scene from another time than the stamp, the estimate would
lead or lag by speed x delay: opposite for the two directions of motion. The estimates must not
depend on the direction of motion (nor err much at all)."""
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
MOVER_X, MOVER_Z = 6.0, 1.0     # the green sphere slides along y, above the red one
MOVER_AMPLITUDE = 0.8           # m: y goes -A .. +A
MOVER_SPEED = 1.0               # m/s
MOVER_RATE = 30.0               # Hz of its tf


def triangle(t, amplitude, speed):
    """Triangle wave of slope +-speed between -amplitude and +amplitude; (value, direction)."""
    period = 4.0 * amplitude / speed
    s = (t % period) / period
    if s < 0.5:
        return -amplitude + 4.0 * amplitude * s, 1
    return 3.0 * amplitude - 4.0 * amplitude * s, -1


def near_turn(t, amplitude, speed, margin=0.1):
    """True within ``margin`` s of a turn of the triangle wave (the speed is not constant there)."""
    half = 2.0 * amplitude / speed
    return min(t % half, half - t % half) < margin


def pan_at(t):
    return triangle(t, AMPLITUDE, SPEED)


def mover_at(t):
    return triangle(t, MOVER_AMPLITUDE, MOVER_SPEED)


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
        self.mover_samples = []
        self.panning = True
        self.next_mover = 0.0
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
        mover = Marker()
        mover.header.frame_id = "mover"     # drawn where tf has the frame: the simulator's scene
        mover.frame_locked = True
        mover.ns, mover.id, mover.type, mover.action = "mover", 0, Marker.SPHERE, Marker.ADD
        mover.pose.orientation.w = 1.0
        mover.scale.x = mover.scale.y = mover.scale.z = 0.4
        mover.color.g, mover.color.a = 1.0, 1.0
        self.markers.publish(MarkerArray(markers=[mk, mover]))
        self.sub = rospy.Subscriber("/pan_cam/image", Image, self.on_image, queue_size=5)

    def tearDown(self):
        self.sub.unregister()

    def broadcast(self):
        t = rospy.Time.now()
        yaw = pan_at(t.to_sec() - self.t0)[0] if self.panning else 0.0
        msg = TransformStamped()
        msg.header.stamp, msg.header.frame_id, msg.child_frame_id = t, "world", "pan_cam"
        q = quaternion(optical(yaw))
        (msg.transform.rotation.x, msg.transform.rotation.y, msg.transform.rotation.z,
         msg.transform.rotation.w) = q
        self.br.sendTransform(msg)
        if t.to_sec() >= self.next_mover:
            self.next_mover = t.to_sec() + 1.0 / MOVER_RATE
            m = TransformStamped()
            m.header.stamp, m.header.frame_id, m.child_frame_id = t, "world", "mover"
            m.transform.translation.x, m.transform.translation.z = MOVER_X, MOVER_Z
            m.transform.translation.y = mover_at(t.to_sec() - self.t0)[0]
            m.transform.rotation.w = 1.0
            self.br.sendTransform(m)

    def on_image(self, msg):
        a = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
        t = msg.header.stamp.to_sec() - self.t0
        if self.panning:
            self.on_pan_image(a, msg.width, t)
        else:
            self.on_mover_image(a, msg.width, t)

    def on_pan_image(self, a, width, t):
        mask = (a[..., 0] > 120) & (a[..., 1] < 60) & (a[..., 2] < 60)
        ys, xs = np.nonzero(mask)
        if len(xs) < 50 or xs.min() == 0 or xs.max() == width - 1:
            return                          # not (wholly) in view
        yaw, direction = pan_at(t)
        if near_turn(t, AMPLITUDE, SPEED):
            return
        bearing = yaw + math.atan((CX - (xs.mean() + 0.5)) / FX)
        with self.lock:
            self.samples.append((direction, bearing, float(ys.mean())))

    def on_mover_image(self, a, width, t):
        mask = (a[..., 1] > 120) & (a[..., 0] < 60) & (a[..., 2] < 60)
        ys, xs = np.nonzero(mask)
        if len(xs) < 30 or xs.min() == 0 or xs.max() == width - 1:
            return
        if near_turn(t, MOVER_AMPLITUDE, MOVER_SPEED):
            return
        y, direction = mover_at(t)
        # camera at the origin looking along +x: image x to the right is world -y
        y_seen = MOVER_X * (CX - (xs.mean() + 0.5)) / FX
        with self.lock:
            self.mover_samples.append((direction, y_seen - y))

    def test_scene_of_the_stamp(self):
        self.panning = False
        end = time.monotonic() + 60.0
        while time.monotonic() < end and not rospy.is_shutdown():
            self.broadcast()
            with self.lock:
                n = [sum(1 for s in self.mover_samples if s[0] == d) for d in (1, -1)]
            if min(n) >= 25:
                break
            rospy.rostime.wallsleep(0.01)
        with self.lock:
            samples = list(self.mover_samples)
        self.assertGreaterEqual(min(n), 25, "images with the moving sphere per direction: %s" % n)
        fwd = np.array([s[1] for s in samples if s[0] == 1])
        back = np.array([s[1] for s in samples if s[0] == -1])
        rospy.loginfo("moving sphere, error of its position: +%.1f m/s mean %.4f m (max %.4f), "
                      "-%.1f m/s mean %.4f m (max %.4f)", MOVER_SPEED, fwd.mean(), np.abs(fwd).max(),
                      MOVER_SPEED, back.mean(), np.abs(back).max())
        # a delay d between the scene drawn and the stamp shifts the two directions by 2 x SPEED x d
        self.assertLess(abs(fwd.mean() - back.mean()), 0.012,
                        "the sphere's position depends on its direction: the scene is not drawn at "
                        "the image's stamp (%.4f vs %.4f m, delay ~%.0f ms)"
                        % (fwd.mean(), back.mean(),
                           1000 * abs(fwd.mean() - back.mean()) / (2 * MOVER_SPEED)))
        self.assertLess(np.abs(np.concatenate([fwd, back])).max(), 0.03)

    def test_pose_of_the_stamp(self):
        self.panning = True
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

"""Records what the tracking evaluation needs: the ball's true pose (/gazebo/model_states), the
network's estimates, each camera's estimates, pixels and last image."""
import threading

import numpy as np
import rospy
from gazebo_msgs.msg import ModelStates
from geometry_msgs.msg import PointStamped
from sensor_msgs.msg import Image
from std_msgs.msg import String


class TrackingRecorder(object):
    def __init__(self, cameras, ball="ball"):
        self.lock = threading.Lock()
        self.ball = ball
        self.truth, self.estimates, self.modes = [], [], []
        self.camera_points = {c: [] for c in cameras}
        self.pixels = {c: [] for c in cameras}
        self.images = {}
        self.subs = [rospy.Subscriber("/gazebo/model_states", ModelStates, self._truth, queue_size=5),
                     rospy.Subscriber("/ptrz_network/ball", PointStamped, self._est, queue_size=50),
                     rospy.Subscriber("/ptrz_network/mode", String, self._mode, queue_size=5)]
        for c in cameras:
            self.subs += [rospy.Subscriber("/%s/ball_point" % c, PointStamped, self._cam_point, c,
                                           queue_size=50),
                          rospy.Subscriber("/%s/ball_pixel" % c, PointStamped, self._pixel, c, queue_size=50),
                          rospy.Subscriber("/%s/camera1/image_raw" % c, Image, self._image, c, queue_size=1)]

    def _truth(self, msg):
        if self.ball in msg.name:
            p = msg.pose[msg.name.index(self.ball)].position
            with self.lock:
                self.truth.append((rospy.get_time(), p.x, p.y))

    def _est(self, msg):
        with self.lock:
            self.estimates.append((msg.header.stamp.to_sec(), msg.point.x, msg.point.y))

    def _mode(self, msg):
        with self.lock:
            self.modes.append((rospy.get_time(), msg.data))

    def _cam_point(self, msg, cam):
        with self.lock:
            self.camera_points[cam].append((msg.header.stamp.to_sec(), msg.point.x, msg.point.y))

    def _pixel(self, msg, cam):
        with self.lock:
            self.pixels[cam].append((msg.point.x, msg.point.y))

    def _image(self, msg, cam):
        if msg.encoding == "rgb8":
            with self.lock:
                self.images[cam] = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).copy()

    def snapshot(self):
        with self.lock:
            return (list(self.truth), list(self.estimates),
                    {k: list(v) for k, v in self.camera_points.items()},
                    {k: list(v) for k, v in self.pixels.items()}, dict(self.images))

"""Records what the tracking evaluation needs: the ball's true pose, the network's estimates, each
camera's estimates, pixels and last image.

The true pose is the simulator's: /gazebo/model_states, and the same link pose on tf
(``gazebo/<ball>/link``). model_states carries no stamp, so its poses are kept with the simulated
time they arrived at, which under load is late by the time this process took to read them (up to
0.5 s measured with three cameras rendering beside it: 48 cm at the ball's speed); tf carries the
simulated time of the step the pose is from. The evaluation takes the stamped poses as the truth
and checks that the model_states poses lie on that path (evaluate.off_path)."""
import threading

import numpy as np
import rospy
from gazebo_msgs.msg import ModelStates
from geometry_msgs.msg import PointStamped
from sensor_msgs.msg import Image
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage


class TrackingRecorder(object):
    def __init__(self, cameras, ball="ball"):
        self.lock = threading.Lock()
        self.ball = ball
        self.frame = "gazebo/%s/link" % ball
        self.truth, self.states, self.estimates, self.modes = [], [], [], []
        self.camera_points = {c: [] for c in cameras}
        self.pixels = {c: [] for c in cameras}
        self.detected = set()       # image times at which a camera detected the ball
        self.images = {}
        self.subs = [rospy.Subscriber("/gazebo/model_states", ModelStates, self._states, queue_size=5),
                     # every tf message (hundreds a second): a dropped one leaves a gap in the truth
                     rospy.Subscriber("/tf", TFMessage, self._tf, queue_size=2000, buff_size=2 ** 24,
                                      tcp_nodelay=True),
                     rospy.Subscriber("/ptrz_network/ball", PointStamped, self._est, queue_size=50),
                     rospy.Subscriber("/ptrz_network/mode", String, self._mode, queue_size=5)]
        for c in cameras:
            self.subs += [rospy.Subscriber("/%s/ball_point" % c, PointStamped, self._cam_point, c,
                                           queue_size=50),
                          rospy.Subscriber("/%s/ball_pixel" % c, PointStamped, self._pixel, c, queue_size=50),
                          rospy.Subscriber("/%s/camera1/image_raw" % c, Image, self._image, c, queue_size=1)]

    def _states(self, msg):
        if self.ball in msg.name:
            p = msg.pose[msg.name.index(self.ball)].position
            with self.lock:
                self.states.append((rospy.get_time(), p.x, p.y))

    def _tf(self, msg):
        for tr in msg.transforms:
            if tr.child_frame_id == self.frame and tr.header.frame_id == "world":
                p = tr.transform.translation
                with self.lock:
                    self.truth.append((tr.header.stamp.to_sec(), p.x, p.y))

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
            self.detected.add(round(msg.header.stamp.to_sec(), 3))

    def _image(self, msg, cam):
        if msg.encoding == "rgb8":
            with self.lock:
                self.images[cam] = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).copy()

    def detection_times(self):
        with self.lock:
            return sorted(self.detected)

    def snapshot(self):
        """(truth (stamped), estimates, {camera: estimates}, {camera: pixels}, {camera: image},
        model_states poses (time of arrival))."""
        with self.lock:
            return (list(self.truth), list(self.estimates),
                    {k: list(v) for k, v in self.camera_points.items()},
                    {k: list(v) for k, v in self.pixels.items()}, dict(self.images), list(self.states))

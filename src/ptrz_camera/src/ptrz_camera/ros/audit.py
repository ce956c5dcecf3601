"""Per-image audit of the tracking: what each camera image shows against what tf says the scene
was at the image's stamp.

For every image of every camera (kept as they arrive: a deep queue), the ball is found as the
network finds it; at the end of a run, with the whole tf history in a buffer, each image gets:

- the camera pose the network uses (tf ``world`` -> the image's header frame, the camera link,
  which robot_state_publisher derives from the camera's ``joint_states``) and the pose the
  renderer drew the image from (the simulator's own link pose: the sensor's optical frame
  ``gazebo/<ns>/<ns>_camera/camera1``), both at the image's stamp, and the angle between them;
- the ball's true position at the stamp (its link pose stamped on tf) projected through each of
  them, against the detected pixel;
- the floor estimate this one image gives (ray through the pixel from the network's pose onto
  z = r) and its distance to the truth;
- for images whose detected pixel is off the projection, the times (camera, ball) at which the
  scene would project onto the detected pixel (a search over tf's history), i.e. the simulated
  time the scene was drawn at.
"""
import threading
from collections import deque

import numpy as np
import rospy
import tf2_ros
from sensor_msgs.msg import CameraInfo, Image, JointState

from ptrz_camera import kinematics, pinhole
from ptrz_camera.tracking import localize, network, segment

#: camera link (x forward, y left, z up) from optical (z forward, x right, y down) coordinates
OPTICAL_TO_LINK = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])


def rotation(q):
    x, y, z, w = q.x, q.y, q.z, q.w
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def pose_of(tr):
    p = tr.transform.translation
    return rotation(tr.transform.rotation), np.array([p.x, p.y, p.z])


def axis_angle(r1, r2):
    """Angle (rad) of the rotation between two rotation matrices."""
    c = (np.trace(r1.T.dot(r2)) - 1.0) / 2.0
    return float(np.arccos(np.clip(c, -1.0, 1.0)))


class ImageAudit(object):
    COLUMNS = ("camera stamp arrival u v area expected_area proj_drawn_u proj_drawn_v pix_err_drawn "
               "proj_net_u proj_net_v pix_err_net cam_angle cam_offset est_x est_y est_err ball_x ball_y "
               "drawn_cam_dt drawn_ball_dt drawn_fit_px joints_angle joints_lin_angle rate").split()

    def __init__(self, cameras, ball="ball", radius=0.11, finder=None, cache=600.0):
        self.cameras = list(cameras)
        self.ball_frame = "gazebo/%s/link" % ball
        self.radius = radius
        self.finder = finder or segment.BallFinder()
        self.lock = threading.Lock()
        self.images = []            # (camera, stamp rospy.Time, frame, Detection or None, arrival)
        self.intr = {}
        self.tf = tf2_ros.Buffer(cache_time=rospy.Duration(cache))
        self.listener = tf2_ros.TransformListener(self.tf)
        self.subs = []
        self.joints = {}
        for c in self.cameras:
            xml = rospy.get_param("/robot_description" if c == "ptrz" else "/%s/robot_description" % c)
            self.joints[c] = network.Camera(c, kinematics.CameraChain(xml))
            for attr in ("joint_times", "joint_values", "joint_rates"):     # the whole run
                setattr(self.joints[c], attr, deque(maxlen=200000))
            self.subs.append(rospy.Subscriber("/%s/joint_states" % c, JointState, self._joint_states, c,
                                              queue_size=500))
            self.subs += [rospy.Subscriber("/%s/camera1/image_raw" % c, Image, self._image, c, queue_size=200,
                                           buff_size=2 ** 24),
                          rospy.Subscriber("/%s/camera1/camera_info" % c, CameraInfo, self._info, c,
                                           queue_size=5)]

    def _joint_states(self, msg, cam):
        with self.lock:
            self.joints[cam].add_joints(msg.header.stamp.to_sec(), dict(zip(msg.name, msg.position)),
                                        dict(zip(msg.name, msg.velocity)))

    def _joint_pose(self, cam, t, cubic=True):
        c = self.joints[cam]
        q = c.joints_at(t, max_gap=0.05)
        if q is None:
            return None
        if not cubic:
            i = list(c.joint_times).index(max(x for x in c.joint_times if x <= t))
            t0, t1 = c.joint_times[i], c.joint_times[min(i + 1, len(c.joint_times) - 1)]
            a = 0.0 if t1 <= t0 else (t - t0) / (t1 - t0)
            q0, q1 = c.joint_values[i], c.joint_values[min(i + 1, len(c.joint_values) - 1)]
            q = {k: q0[k] + a * (q1[k] - q0[k]) for k in q0}
        return c.chain.pose(q)

    def _info(self, msg, cam):
        if msg.width > 0 and msg.K[0] > 0:
            with self.lock:
                self.intr[cam] = pinhole.intrinsics_from_camera_info(msg)

    def _image(self, msg, cam):
        if msg.encoding != "rgb8":
            return
        rgb = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3)
        det = self.finder.find(rgb)
        with self.lock:
            self.images.append((cam, msg.header.stamp, msg.header.frame_id, det, rospy.get_time()))

    def optical_frame(self, cam):
        return "gazebo/%s/%s_camera/camera1" % (cam, cam) if cam != "ptrz" else "gazebo/ptrz/camera/camera1"

    def _lookup(self, frame, stamp):
        try:
            return pose_of(self.tf.lookup_transform("world", frame, stamp))
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException):
            return None

    def _drawn_pose(self, cam, stamp):
        p = self._lookup(self.optical_frame(cam), stamp)
        if p is None:
            return None
        return p[0].dot(OPTICAL_TO_LINK.T), p[1]

    def _fit_times(self, cam, stamp, intr, u, v, span=0.4, step=0.005):
        """(camera dt, ball dt, residual px): the times relative to the stamp at which the drawn
        camera pose and the ball project onto (u, v) best (grid search)."""
        offsets = np.arange(-span, 0.1 + 1e-9, step)
        cams, balls = [], []
        for dt in offsets:
            t = stamp + rospy.Duration.from_sec(dt) if dt >= -stamp.to_sec() else stamp
            cams.append(self._drawn_pose(cam, t))
            b = self._lookup(self.ball_frame, t)
            balls.append(None if b is None else b[1])
        best = (float("nan"), float("nan"), float("inf"))
        for i, cp in enumerate(cams):
            if cp is None:
                continue
            for j, bp in enumerate(balls):
                if bp is None:
                    continue
                px = pinhole.project(intr, pinhole.to_camera(cp, bp))
                if px is None:
                    continue
                err = float(np.hypot(px[0] - u, px[1] - v))
                if err < best[2]:
                    best = (float(offsets[i]), float(offsets[j]), err)
        return best

    def rows(self, t_from=0.0, fit_above_px=1.5):
        with self.lock:
            images = list(self.images)
            intrs = dict(self.intr)
        out = []
        nan = float("nan")
        for cam, stamp, frame, det, arrival in images:
            if stamp.to_sec() < t_from or det is None or cam not in intrs:
                continue
            intr = intrs[cam]
            net = self._lookup(frame, stamp)
            drawn = self._drawn_pose(cam, stamp)
            ball = self._lookup(self.ball_frame, stamp)
            if net is None or drawn is None or ball is None:
                continue
            b = ball[1]
            pd = pinhole.project(intr, pinhole.to_camera(drawn, b)) or (nan, nan)
            pn = pinhole.project(intr, pinhole.to_camera(net, b)) or (nan, nan)
            rng = np.linalg.norm(b - net[1])
            expected = np.pi * (intr.fx * self.radius / rng) ** 2
            with self.lock:
                jp = self._joint_pose(cam, stamp.to_sec())
                jl = self._joint_pose(cam, stamp.to_sec(), cubic=False)
            # the floor estimate from the pose the network uses (joint states, else tf)
            est = localize.floor_estimate(jp if jp is not None else net, intr, det.u, det.v, self.radius)
            ex, ey = (est.xy if est is not None else (nan, nan))
            err_d = float(np.hypot(pd[0] - det.u, pd[1] - det.v))
            jang = axis_angle(jp[0], drawn[0]) if jp is not None else nan
            jlang = axis_angle(jl[0], drawn[0]) if jl is not None else nan
            fit = (nan, nan, nan)
            if not err_d <= fit_above_px:
                fit = self._fit_times(cam, stamp, intr, det.u, det.v)
            out.append((cam, stamp.to_sec(), arrival, det.u, det.v, det.area, expected, pd[0], pd[1], err_d,
                        pn[0], pn[1], float(np.hypot(pn[0] - det.u, pn[1] - det.v)),
                        axis_angle(net[0], drawn[0]), float(np.linalg.norm(net[1] - drawn[1])),
                        ex, ey, float(np.hypot(ex - b[0], ey - b[1])), b[0], b[1]) + fit
                       + (jang, jlang, self.joints[cam].speed_at(stamp.to_sec())))
        return out

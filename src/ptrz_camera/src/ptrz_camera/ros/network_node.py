"""ptrz_network: the camera network at work (ptrz_camera.tracking.network behind ROS topics).

Per camera <ns>: in <ns>/camera1/image_raw, <ns>/camera1/camera_info, <ns>/joint_states, tf (the
camera pose at each image's stamp: world -> the image's frame_id, the camera link) and the
camera's robot_description; out <ns>/pan_position_controller/command and tilt, <ns>/ball_point
(PointStamped, world: this camera's floor estimate) and <ns>/ball_pixel (PointStamped, frame
'image': x = u, y = v, z = area in px). For the network: /ptrz_network/ball (PointStamped, world:
the fused floor position, z = the ball's radius), /ptrz_network/coverage (nav_msgs/OccupancyGrid:
-1 never seen, 0 seen now ... 100 not seen for ~stale_time s) and /ptrz_network/mode (tracking |
scanning)."""
import threading
import time

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import PointStamped
from nav_msgs.msg import OccupancyGrid
from sensor_msgs.msg import CameraInfo, Image, JointState
from std_msgs.msg import Float64, String

from ptrz_camera import kinematics, pinhole
from ptrz_camera.errors import PtrzError
from ptrz_camera.tracking import localize, network, segment
from ptrz_camera.worlds import FIELD


def description_param(ns):
    return "/robot_description" if ns == "ptrz" else "/%s/robot_description" % ns


class CameraIO(object):
    def __init__(self, ns, node):
        self.ns = ns
        self.lock = threading.Lock()
        self.image = None
        self.intr = None
        self.pan = rospy.Publisher("/%s/pan_position_controller/command" % ns, Float64, queue_size=1)
        self.tilt = rospy.Publisher("/%s/tilt_position_controller/command" % ns, Float64, queue_size=1)
        self.point = rospy.Publisher("/%s/ball_point" % ns, PointStamped, queue_size=5)
        self.pixel = rospy.Publisher("/%s/ball_pixel" % ns, PointStamped, queue_size=5)
        self.subs = [rospy.Subscriber("/%s/camera1/image_raw" % ns, Image, self._on_image, queue_size=1),
                     rospy.Subscriber("/%s/camera1/camera_info" % ns, CameraInfo, self._on_info,
                                      queue_size=1),
                     rospy.Subscriber("/%s/joint_states" % ns, JointState, node.on_joints, callback_args=ns,
                                      queue_size=50)]

    def _on_image(self, msg):
        with self.lock:
            self.image = (msg, time.monotonic())

    def _on_info(self, msg):
        if msg.width > 0 and msg.K[0] > 0:
            with self.lock:
                self.intr = pinhole.intrinsics_from_camera_info(msg)

    def take(self):
        """((image, wall time of arrival) or None, intrinsics)."""
        with self.lock:
            img, self.image = self.image, None
            return img, self.intr

    def put_back(self, item):
        """An image whose pose is not in tf yet is tried again, unless a newer one came in."""
        with self.lock:
            if self.image is None:
                self.image = item


class NetworkNode(object):
    def __init__(self, names, floor, radius, rate, finder, lead):
        chains = {}
        for ns in names:
            param = description_param(ns)
            xml = rospy.get_param(param, None)
            if not xml:
                raise PtrzError("camera %s: no robot description on %s (start ptrz.launch first)"
                                % (ns, param))
            chains[ns] = kinematics.CameraChain(xml)
        self.core = network.Network(chains, floor, radius, finder=finder, lead=lead)
        self.core_lock = threading.Lock()
        self.rate = rate
        self.io = {ns: CameraIO(ns, self) for ns in names}
        self.tf = tf2_ros.Buffer(cache_time=rospy.Duration(30.0))
        self.tf_listener = tf2_ros.TransformListener(self.tf)
        self.ball_pub = rospy.Publisher("/ptrz_network/ball", PointStamped, queue_size=10)
        self.grid_pub = rospy.Publisher("/ptrz_network/coverage", OccupancyGrid, queue_size=1, latch=True)
        self.mode_pub = rospy.Publisher("/ptrz_network/mode", String, queue_size=1, latch=True)
        self.last_mode = None
        self.pose_from = rospy.get_param("~pose_from", "joints")
        if self.pose_from not in ("joints", "tf"):
            raise PtrzError("~pose_from must be 'joints' or 'tf', got %r" % (self.pose_from,))
        self.max_joint_gap = float(rospy.get_param("~max_joint_gap", 0.05))
        self.log = None
        path = rospy.get_param("~log", "")
        if path:
            self.log = open(path, "w")
            self.log.write("t x y n residual sources(camera:stamp:u:v:area:x:y:pan:tilt:fk_angle)\n")

    def on_joints(self, msg, ns):
        q = {n: p for n, p in zip(msg.name, msg.position)}
        v = {n: x for n, x in zip(msg.name, msg.velocity)} if len(msg.velocity) == len(msg.name) else None
        with self.core_lock:
            self.core.on_joints(ns, msg.header.stamp.to_sec(), q, v)

    def camera_pose(self, ns, img):
        """(R, t) of the camera link at the image's stamp; None while it is not known yet, False
        when it never will be. From the camera's joint states around the stamp (positions and
        velocities, cubic between the two samples: the forward kinematics of the camera's own
        description) when ~pose_from is "joints" and the image's frame is the camera link; else,
        or when the joint states around the stamp are missing, from tf (robot_state_publisher's
        transforms of the same joint states, which it samples with a queue of one and tf
        interpolates linearly: up to 27 mrad off the drawn pose while a camera slews at
        start-up)."""
        if self.pose_from == "joints":
            cam = self.core.cameras[ns]
            if img.header.frame_id.lstrip("/") == cam.chain.camera_link:
                t = img.header.stamp.to_sec()
                with self.core_lock:
                    q = cam.joints_at(t, max_gap=self.max_joint_gap)
                    until = cam.joints_until()
                if q is not None:
                    return cam.chain.pose(q)
                if until is None or until < t:
                    return None
        return self.pose_at(img)

    def pose_at(self, img):
        """(R, t) of the image's frame (the camera link) in the world at the image's stamp, from
        tf; None while tf has not reached that time yet, False when it never will."""
        try:
            tr = self.tf.lookup_transform("world", img.header.frame_id, img.header.stamp)
        except tf2_ros.ExtrapolationException as exc:
            return None if "future" in str(exc) else False
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException):
            return False
        q = tr.transform.rotation
        p = tr.transform.translation
        x, y, z, w = q.x, q.y, q.z, q.w
        rot = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        return rot, np.array([p.x, p.y, p.z])

    def step(self):
        t = rospy.get_time()
        for ns, io in self.io.items():
            item, intr = io.take()
            if item is None or intr is None or item[0].encoding != "rgb8":
                continue
            img = item[0]
            pose = self.camera_pose(ns, img)
            if pose is None and time.monotonic() - item[1] < 1.0:
                io.put_back(item)
                continue
            if not pose:
                rospy.logwarn_throttle(10.0, "ptrz_network: %s: no camera pose for %s at the image's time "
                                       "%.3f in tf; image skipped"
                                       % (ns, img.header.frame_id, img.header.stamp.to_sec()))
                continue
            rgb = np.frombuffer(img.data, np.uint8).reshape(img.height, img.width, 3)
            stamp = img.header.stamp.to_sec()
            with self.core_lock:
                obs = self.core.on_image(ns, stamp, rgb, intr, pose)
            if obs is not None and obs.detection is not None:
                px = PointStamped()
                px.header.stamp, px.header.frame_id = img.header.stamp, "image"
                px.point.x, px.point.y, px.point.z = obs.detection.u, obs.detection.v, obs.detection.area
                io.pixel.publish(px)
                if obs.estimate is not None:
                    io.point.publish(self._point(img.header.stamp, obs.estimate.xy))
        with self.core_lock:
            fused_all = [((t_, est), src) for t_, est, src in self.core.fuse_ready()]
            settled = {}
            for ns, cam in self.core.cameras.items():
                settled[ns] = (cam.command is not None and abs(cam.q.get("pan", 0) - cam.command[0]) < 0.02
                               and abs(cam.q.get("tilt", 0) - cam.command[1]) < 0.02)
            cmds = self.core.commands(t, settled)
            mode = self.core.mode
        for fused, sources in fused_all:
            self.ball_pub.publish(self._point(rospy.Time.from_sec(fused[0]), fused[1].xy))
            if self.log is not None:
                self._log(fused, sources)
        for ns, (pan, tilt) in cmds.items():
            io = self.io[ns]          # every step: a late-connecting controller still gets it
            io.pan.publish(Float64(pan))
            io.tilt.publish(Float64(tilt))
        if mode != self.last_mode:
            self.mode_pub.publish(String(mode))
            rospy.loginfo("ptrz_network: %s" % mode)
            self.last_mode = mode

    def _log(self, fused, sources):
        """One line per fused estimate: which cameras, their pixels and floor points, the joint
        angles at the image's time and the angle between their forward kinematics and the tf pose
        used, and how far apart the rays pass."""
        t, est = fused
        rr = localize.ray_residual([o.ray for _n, o in sources if o.ray is not None])
        parts = []
        with self.core_lock:
            for name, o in sources:
                cam = self.core.cameras[name]
                q = cam.joints_at(o.t) or {}
                ang = float("nan")
                if q and o.pose is not None:
                    rot = cam.chain.pose(q)[0]
                    ang = float(np.arccos(np.clip((np.trace(rot.T.dot(o.pose[0])) - 1) / 2, -1, 1)))
                parts.append("%s:%.3f:%.2f:%.2f:%d:%.4f:%.4f:%.4f:%.4f:%.5f" % (
                    name, o.t, o.detection.u, o.detection.v, o.detection.area, o.estimate.xy[0],
                    o.estimate.xy[1], q.get("pan", float("nan")), q.get("tilt", float("nan")), ang))
        res = rr[1] if rr else float("nan")
        self.log.write("%.3f %.4f %.4f %d %.4f %s\n"
                       % (t, est.xy[0], est.xy[1], len(sources), res, " ".join(parts)))
        self.log.flush()

    def _point(self, stamp, xy):
        p = PointStamped()
        p.header.stamp, p.header.frame_id = stamp, "world"
        p.point.x, p.point.y, p.point.z = float(xy[0]), float(xy[1]), self.core.radius
        return p

    def publish_grid(self):
        t = rospy.get_time()
        with self.core_lock:
            g = self.core.grid
            data = g.values(t)
        msg = OccupancyGrid()
        msg.header.stamp, msg.header.frame_id = rospy.Time.from_sec(t), "world"
        msg.info.resolution = g.resolution
        msg.info.width, msg.info.height = g.nx, g.ny
        msg.info.origin.position.x, msg.info.origin.position.y = g.x0, g.y0
        msg.info.origin.orientation.w = 1.0
        msg.data = data.ravel().tolist()
        self.grid_pub.publish(msg)

    def report(self):
        """The verdicts on the image times with a detection (published, or why not)."""
        with self.core_lock:
            c = dict(self.core.counts)
        n = max(1, c.get("detected", 0))
        text = ("ptrz_network: %d image times with the ball detected: %d estimates published (%.1f %%); "
                "none from %d without a floor estimate (ball partly hidden), %d while no camera had "
                "locked on, %d with the ball at the image's edge, %d whose rays disagreed; %d times a "
                "camera whose ray disagreed was left out"
                % (c.get("detected", 0), c.get("published", 0), 100.0 * c.get("published", 0) / n,
                   c.get("no_estimate", 0), c.get("rejected_not_locked", 0), c.get("rejected_edge", 0),
                   c.get("rejected_residual", 0), c.get("left_out", 0)))
        print(text, flush=True)
        if self.log is not None:
            self.log.write("# " + text + "\n")
            self.log.flush()

    def run(self):
        next_grid = 0.0
        while not rospy.is_shutdown():
            self.step()
            now = time.monotonic()
            if now >= next_grid:
                self.publish_grid()
                next_grid = now + 1.0
            try:
                rospy.rostime.wallsleep(1.0 / self.rate)
            except rospy.ROSInterruptException:
                return


def main():
    rospy.init_node("ptrz_network")
    names = rospy.get_param("~cameras", None) or rospy.get_param("/ptrz_network/cameras", "ptrz")
    if isinstance(names, str):
        names = names.split()
    floor = rospy.get_param("~floor", [FIELD.centre_x - FIELD.length / 2, FIELD.centre_y - FIELD.width / 2,
                                       FIELD.length, FIELD.width])
    finder = segment.BallFinder(tuple(rospy.get_param("~hsv_low", list(segment.MAGENTA[0]))),
                                tuple(rospy.get_param("~hsv_high", list(segment.MAGENTA[1]))))
    try:
        rospy.wait_for_message("/clock", rospy.AnyMsg, timeout=120)
        node = NetworkNode(names, tuple(floor), float(rospy.get_param("~ball_radius", 0.11)),
                           float(rospy.get_param("~rate", 30.0)), finder,
                           float(rospy.get_param("~lead", 0.25)))
    except (PtrzError, rospy.ROSException) as exc:
        rospy.logerr("ptrz_network: %s" % exc)
        return 2
    try:
        node.run()
    finally:
        node.report()
    return 0

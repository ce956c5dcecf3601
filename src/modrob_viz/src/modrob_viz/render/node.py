"""ROS layer of the ``camera_renderer`` node: cameras from ``~cameras`` and from the simulator's
camera sensors (``~sensors_param``), rendered by :class:`RvizScene`, published as
``sensor_msgs/Image`` (+ ``CameraInfo`` when asked).

An image is the view of the scene at its stamp. Frames are started in batches: the cameras due
together are drawn at one tf time T, the newest time at which tf has every camera frame of the
batch and every frame the scene's frame-locked markers hang on (``scene_sync``). RViz's frame
manager is set to T (exact sync), so the scene's objects are drawn where they were at T; each
camera's 1x1 placeholder image carries T, so RViz's Camera display takes the camera's pose at T;
the frames are grabbed once RViz has drawn the placeholders, and the images are stamped T. A user
can look the camera pose up in tf at the image's stamp and cast rays from it, also while the
camera and the objects move. The next batch starts only when the last one is grabbed (RViz has
one frame manager time). When nothing moves (only static frames), images are stamped with the
time of the grab.

A camera is drawn only while one of its output topics has a subscriber (or it records), like a
Gazebo camera sensor: one nobody listens to has its RViz display disabled and costs nothing; with
no camera wanted the loop slows down (``IDLE_TICK``).

Callbacks only store the latest CameraInfo and the scene's frames; a Qt timer in the main thread
does all the work (RViz is not thread-safe). Problems with one camera (no intrinsics, zero-size
CameraInfo, frame missing from tf) are logged once with what to do, and only that camera waits.
"""
import collections
import os
import threading
import time

import numpy as np
import rospkg
import rospy
import tf2_ros
from python_qt_binding.QtCore import QTimer
from sensor_msgs.msg import CameraInfo, Image, PointCloud2, PointField
from std_msgs.msg import Empty
from std_srvs.srv import Trigger, TriggerResponse
from visualization_msgs.msg import Marker, MarkerArray

from modrob_msgs.errors import ModrobError
from modrob_viz.errors import ConfigError
from modrob_viz.render import camera_spec, depth, lens, pinhole, scene_sync
from modrob_viz.render.video import VideoRecorder, save_png

#: s a camera given to RViz may take to come up before it is given again (RViz resets its displays
#: when the time jumps back, and a CameraInfo sent before that, or before RViz subscribed, is lost)
SHOW_AGAIN = 2.0
TICK, IDLE_TICK = 2, 50     # ms between two passes of the loop: some camera wanted / none
#: s of wall time a camera stays drawn after its last subscriber left (a client that takes one
#: message at a time, such as rospy.wait_for_message in a loop, does not switch it off and on)
KEEP_ACTIVE = 2.0


def _image(stamp, frame_id, arr, encoding, step):
    msg = Image()
    msg.header.stamp, msg.header.frame_id = stamp, frame_id
    msg.height, msg.width = arr.shape[0], arr.shape[1]
    msg.encoding, msg.is_bigendian, msg.step = encoding, 0, step
    msg.data = arr.tobytes()
    return msg


class _Camera(object):
    def __init__(self, spec):
        self.spec = spec
        self.info = None            # latest input CameraInfo (or None)
        self.intrinsics = spec["intrinsics"]
        self.shown = None           # (frame, intrinsics) given to RViz last
        self.shown_at = None        # and when (monotonic s)
        self.rviz_ready = False     # RViz has had its CameraInfo and placeholder
        self.blank = None           # the 1x1 background image whose header names the frame
        self.next_t = 0.0
        self.problem = None         # text of the problem logged last (logged once)
        self.sub = None
        self.pub_image = rospy.Publisher(spec["image"], Image, queue_size=1)
        self.pub_info = rospy.Publisher(spec["camera_info_out"], CameraInfo, queue_size=1) \
            if spec["camera_info_out"] else None
        # a depth camera's outputs (None when not asked for)
        self.pub_depth = rospy.Publisher(spec["depth_image"], Image, queue_size=1) \
            if spec["depth_image"] else None
        self.pub_depth_info = rospy.Publisher(spec["depth_camera_info"], CameraInfo, queue_size=1) \
            if spec["depth_camera_info"] else None
        self.pub_points = rospy.Publisher(spec["points"], PointCloud2, queue_size=1) \
            if spec["points"] else None
        self.rays = None            # (intrinsics, pixel rays) of the last point cloud
        self.lens_maps = None       # (intrinsics, lens.source_maps) of the last distorted image
        self.triggers = 0           # frames asked for by the trigger topic and not yet published
        self.trigger_sub = None
        prefix = rospy.get_name() + "/" + spec["id"]
        self.pub_blank = rospy.Publisher(prefix + "/image", Image, queue_size=1, latch=True)
        self.pub_rviz_info = rospy.Publisher(prefix + "/camera_info", CameraInfo, queue_size=1, latch=True)
        self.last_rgb = None
        self.frames = 0
        self.recorder = None
        # frame in flight: (RViz image count, intrinsics, frame, RViz's render count of the camera
        # when the placeholder was sent, None without the ClipCamera plugin)
        self.pending = None
        self.active = True          # its RViz display is enabled (drawn)
        self.wanted_at = None       # monotonic s it was last wanted

    def outputs(self):
        """The publishers a subscriber of which makes the camera wanted."""
        return [p for p in (self.pub_image, self.pub_info, self.pub_depth, self.pub_depth_info,
                            self.pub_points) if p is not None]

    def wanted(self):
        return self.recorder is not None or any(p.get_num_connections() > 0 for p in self.outputs())

    def close(self):
        for p in (self.pub_image, self.pub_info, self.pub_depth, self.pub_depth_info, self.pub_points,
                  self.pub_blank, self.pub_rviz_info, self.sub, self.trigger_sub):
            if p is not None:
                p.unregister()
        if self.recorder is not None:
            self.recorder.close()


# Saved frames and videos, like ROS's own files under ROS_HOME: not /tmp, where a second user of
# the machine could not write them and a reboot may clear them.
DEFAULT_OUTPUT_DIR = os.path.join(rospkg.get_ros_home(), "modrob_viz", "cameras")


class CameraRendererNode(object):
    def __init__(self, scene, cameras, rate, fixed_frame="world", sensors_param="",
                 output_dir=DEFAULT_OUTPUT_DIR, record=(), video_fps=None, seed=0,
                 background=(178, 178, 178), scene_max_lag=1.0):
        """``scene_max_lag`` (s): a scene frame whose tf is that much older than the newest is
        left out of the batch time (its publisher stopped; see scene_sync.common_stamp)."""
        self.scene = scene
        self.rate = rate
        self.background = bytes(bytearray(int(c) & 255 for c in background))
        self.fixed_frame = fixed_frame
        self.sensors_param = sensors_param
        self.output_dir = output_dir
        self.video_fps = video_fps
        self.rng = np.random.default_rng(seed)
        self.lock = threading.Lock()
        self.rec_lock = threading.Lock()    # cameras' recorders: Qt thread writes, services start/stop
        self.cams = {}
        self.static_ids = set()
        self.tf_buffer = tf2_ros.Buffer(cache_time=rospy.Duration(10.0))
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
        self.scene_frames = scene_sync.SceneFrames()     # frames of the frame-locked scene markers
        self.scene_lock = threading.Lock()
        self.scene_max_lag_ns = int(scene_max_lag * 1e9)
        self.left_out = []          # scene frames left out of the batch time (logged on change)
        self.batch = None           # (T, wall time started) of the frames in flight
        self.batches = 0
        self.resyncs = 0            # times RViz's time had moved away from T (set again)
        self.redraws = 0            # placeholders sent again (the camera was not drawn at T)
        self.shown_again = 0        # CameraInfo given to RViz again (its display had reset or not come up)
        self.tf_wait_since = None   # when the batch waiting for RViz's tf at T began to wait
        self.tf_waits = 0           # batches that waited for RViz's tf to reach their time
        self.tf_waits_expired = 0   # batches that went ahead after waiting 1 s for it
        self.batch_frames = []      # camera and scene frames of the batch time (_batch_stamp)
        self.dropped = 0            # frames given up after 1 s
        self.batch_time = 0.0       # wall time batches were in flight
        self._scene_subs = [self._subscribe_scene(topic, kind) for topic, kind in scene.scene_topics()]
        for spec in cameras:
            self._add(spec)
            self.static_ids.add(spec["id"])
        self._sensor_specs = {}
        self._next_sensor_poll = 0.0
        rospy.Service("~save_frame", Trigger, self._srv_save_frame)
        rospy.Service("~start_recording", Trigger, self._srv_start_recording)
        rospy.Service("~stop_recording", Trigger, self._srv_stop_recording)
        self.record = list(record)      # cameras to record from their first frame ("all")
        if record:
            self._start_recording(None if record == ["all"] else record)
        self.timer = QTimer()
        self.timer.timeout.connect(self._tick)
        self.idle_frames = 0        # camera frames not drawn: nobody subscribed
        self.timer.start(TICK)
        rospy.on_shutdown(self._on_shutdown)

    # ---- the scene's frames ----------------------------------------------------------------------
    def _subscribe_scene(self, topic, kind):
        if kind == "MarkerArray":
            return rospy.Subscriber(topic, MarkerArray, self._on_scene, (topic, True), queue_size=10)
        return rospy.Subscriber(topic, Marker, self._on_scene, (topic, False), queue_size=100)

    def _on_scene(self, msg, args):
        topic, is_array = args
        with self.scene_lock:
            self.scene_frames.update(topic, msg.markers if is_array else [msg])

    def _newest(self, frame):
        """Newest tf stamp of ``frame`` in the fixed frame (ns; 0 static; None not in tf)."""
        try:
            return self.tf_buffer.lookup_transform(self.fixed_frame, frame,
                                                   rospy.Time(0)).header.stamp.to_nsec()
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException, tf2_ros.InvalidArgumentException):
            return None

    def _batch_stamp(self, frames):
        """The time T to draw the cameras on ``frames`` at (scene_sync.common_stamp), or None
        when a camera frame is not in tf."""
        cams = [self._newest(f) for f in frames]
        if any(c is None for c in cams):
            return None
        with self.scene_lock:
            scene = self.scene_frames.frames()
        stamps = {f: self._newest(f) for f in scene}
        t, left_out = scene_sync.common_stamp(cams, stamps, self.scene_max_lag_ns)
        # the frames RViz must have at T too (those in this node's tf and not left out)
        self.batch_frames = list(frames) + sorted(f for f, v in stamps.items()
                                                  if v is not None and f not in left_out)
        if left_out != self.left_out:
            self.left_out = left_out
            if left_out:
                rospy.logwarn("scene frame(s) %s: no tf for more than %.1f s; the images no longer wait "
                              "for them and RViz cannot draw their objects at the images' time",
                              ", ".join(left_out[:5]) + (" ..." if len(left_out) > 5 else ""),
                              self.scene_max_lag_ns / 1e9)
        return rospy.Time(nsecs=t)

    # ---- cameras --------------------------------------------------------------------------------
    def _add(self, spec):
        try:
            self.scene.add_camera(spec["id"], rospy.get_name() + "/" + spec["id"])
        except ConfigError as err:
            rospy.logerr("%s", err)
            return
        cam = _Camera(spec)
        if spec["camera_info"]:
            cam.sub = rospy.Subscriber(spec["camera_info"], CameraInfo, self._on_info, cam, queue_size=1)
        if spec["trigger"]:
            cam.trigger_sub = rospy.Subscriber(spec["trigger"], Empty, self._on_trigger, cam, queue_size=100)
        if getattr(self, "record", None) and ("all" in self.record or spec["name"] in self.record):
            try:
                cam.recorder = VideoRecorder(os.path.join(self.output_dir, "%s.avi" % spec["id"]),
                                             self.video_fps or spec["rate"])
            except ConfigError as err:
                rospy.logerr("camera '%s': not recorded: %s", spec["name"], err)
        with self.lock:
            self.cams[spec["id"]] = cam
            rates = [c.spec["rate"] for c in self.cams.values()]
        self.scene.set_frame_rate(min(120.0, 2.0 * max(rates + [self.rate])))
        rospy.loginfo("camera '%s': %s -> %s at %.1f Hz", spec["name"],
                      spec["camera_info"] or "fixed intrinsics",
                      spec["image"], spec["rate"])

    def _remove(self, cid):
        with self.lock:
            cam = self.cams.pop(cid, None)
        if cam is not None:
            cam.pending = None
            cam.close()
            self.scene.remove_camera(cid)
            rospy.loginfo("camera '%s' removed", cam.spec["name"])

    def _on_trigger(self, _msg, cam):
        with self.lock:
            cam.triggers += 1

    def _on_info(self, msg, cam):
        cam.info = msg      # stored only; the Qt thread uses it

    def _poll_sensors(self):
        """Cameras registered by the simulator's camera sensor plugins (added/removed/changed)."""
        if not self.sensors_param:
            return
        try:
            raw = rospy.get_param(self.sensors_param, {})
        except (KeyError, OSError):
            raw = {}
        if not isinstance(raw, dict):
            raw = {}
        specs = {}
        for key, value in raw.items():
            try:
                if isinstance(value, dict):
                    value = dict(value, name=value.get("name", key))
                spec = camera_spec.parse(value,
                                         self.rate, "%s/%s" % (self.sensors_param, key))
            except ModrobError as err:
                if self._sensor_specs.get(key) != "bad":
                    rospy.logerr("camera sensor %s ignored: %s", key, err)
                specs[key] = "bad"
                continue
            specs[key] = spec
        # two sensors of one name (or a name ~cameras uses): their keys (model__sensor) are unique
        ids = collections.Counter(v["id"] for v in specs.values() if isinstance(v, dict))
        for key, spec in specs.items():
            if isinstance(spec, dict) and (ids[spec["id"]] > 1 or spec["id"] in self.static_ids):
                spec["id"] = camera_spec.internal_name(key)
        for key, old in self._sensor_specs.items():     # removed or changed ones first
            if isinstance(old, dict) and specs.get(key) != old:
                self._remove(old["id"])
        for key, spec in specs.items():
            if spec == "bad" or self._sensor_specs.get(key) == spec:
                continue
            if spec["id"] in self.static_ids:
                rospy.logerr("camera sensor %s: id %s is already used by ~cameras", key, spec["id"])
                continue
            self._add(spec)
        self._sensor_specs = specs

    def _problem(self, cam, text):
        if cam.problem != text:
            cam.problem = text
            rospy.logwarn("camera '%s': %s", cam.spec["name"], text)

    def _ready(self, cam):
        """(frame, intrinsics) to render with, or None after logging why not."""
        spec = cam.spec
        info = cam.info
        if spec["camera_info"]:
            if info is None:
                self._problem(cam, "waiting for its CameraInfo on %s" % spec["camera_info"])
                return None
            try:
                intr = pinhole.from_matrices(info.width, info.height, info.K, info.P)
            except ConfigError as err:
                self._problem(cam, "unusable CameraInfo on %s (%s); waiting for a valid one"
                              % (spec["camera_info"], err))
                return None
            frame = spec["frame"] or info.header.frame_id
        else:
            intr, frame = cam.intrinsics, spec["frame"]
        if not frame:
            self._problem(cam, "no frame to render from: the CameraInfo header has no frame_id and "
                               "the camera no 'frame'")
            return None
        if not self.tf_buffer.can_transform(self.fixed_frame, frame.lstrip("/"), rospy.Time(0)):
            self._problem(cam, "frame '%s' is not in tf (no transform to '%s'); waiting for it"
                          % (frame, self.fixed_frame))
            return None
        if cam.problem is not None:
            rospy.loginfo("camera '%s': rendering (frame '%s', %dx%d)", spec["name"], frame,
                          intr.width, intr.height)
            cam.problem = None
        return frame.lstrip("/"), intr

    def _show(self, cam, frame, intr):
        """Give RViz the camera's frame and pinhole (only when they change)."""
        if cam.shown == (frame, intr):
            return
        cam.shown = (frame, intr)
        cam.shown_at = time.monotonic()
        info = CameraInfo()
        info.header.frame_id = frame
        info.width, info.height = intr.width, intr.height
        drawn = pinhole.rviz_intrinsics(intr)
        info.K = pinhole.k_matrix(drawn)
        info.P = pinhole.p_matrix(drawn)
        info.R = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
        info.distortion_model = "plumb_bob"
        info.D = [0.0] * 5
        blank = Image()
        blank.header.frame_id = frame           # stamp 0: RViz uses the latest transform
        blank.width = blank.height = 1
        blank.encoding, blank.step, blank.data = "rgb8", 3, self.background
        cam.pub_rviz_info.publish(info)
        cam.blank = blank
        cam.pub_blank.publish(blank)
        self.scene.resize_camera(cam.spec["id"], intr.width, intr.height)
        self.scene.set_clip(cam.spec["id"], cam.spec["clip_near"], cam.spec["clip_far"])
        if cam.spec["depth"] and not self.scene.set_depth(cam.spec["id"], True):
            self._problem(cam, "no depth: the ClipCamera rviz plugin with pixels read from OpenGL is "
                               "needed (build the workspace; ~pixels gl)")
        if not self.scene.fits(cam.spec["id"]):
            sw, sh = self.scene.screen_size()
            self._problem(cam, "does not fit on the X screen (%dx%d) beside the other cameras: "
                               "fewer/smaller cameras or a larger screen (~screen)" % (sw, sh))

    def _out_info(self, cam, intr, stamp, header_frame):
        info = CameraInfo()
        info.header.stamp, info.header.frame_id = stamp, header_frame
        info.width, info.height = intr.width, intr.height
        info.K = pinhole.k_matrix(intr)
        info.P = pinhole.p_matrix(intr, -intr.fx * cam.spec["hack_baseline"])
        info.R = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
        src = cam.info
        info.distortion_model = (src.distortion_model if src is not None and src.distortion_model
                                 else "plumb_bob")
        info.D = list(src.D) if src is not None and len(src.D) else [0.0] * 5
        return info

    # ---- the loop (Qt thread) ----------------------------------------------------------------------
    def _tick(self):
        if rospy.is_shutdown():
            self.scene.app.quit()
            return
        now = time.monotonic()
        if now >= self._next_sensor_poll:
            self._next_sensor_poll = now + 1.0
            self._poll_sensors()
        with self.lock:
            cams = list(self.cams.values())
        self._activate(cams)
        if self.batch is not None:
            self._collect(cams, now)
            if self.batch is not None:
                return                  # RViz draws at the batch's time until it is grabbed
        if not any(now >= cam.next_t for cam in cams):
            return
        due = []
        for cam in cams:
            # a camera due within half its period joins the batch: cameras of one rate fall into
            # step and share batches (each batch costs RViz a pass)
            if cam.spec["trigger"]:
                # a triggered camera: a frame while a trigger waits (and none is in flight)
                if cam.triggers <= 0 or cam.pending is not None:
                    continue
            elif now < cam.next_t - 0.5 / cam.spec["rate"]:
                continue
            else:
                cam.next_t = max(cam.next_t + 1.0 / cam.spec["rate"], now - 0.5 / cam.spec["rate"])
            ready = self._ready(cam)        # says what keeps it from rendering, also when idle
            if not cam.active:
                self.idle_frames += 1
                continue
            if ready is None:
                continue
            frame, intr = ready
            shown_before = cam.shown == (frame, intr)
            self._show(cam, frame, intr)
            if not shown_before:
                continue            # RViz renders the new pinhole on its next frame
            if not self.scene.ready(cam.spec["id"]):
                if cam.rviz_ready or now - cam.shown_at > SHOW_AGAIN:
                    # RViz resets its displays when the time jumps back (a simulator restart)
                    # and forgets the CameraInfo: give it again at the camera's next frame. Also
                    # when a camera given to RViz has not come up within SHOW_AGAIN: a camera
                    # made anew by that restart was given its CameraInfo just before RViz reset
                    # (or before RViz subscribed), and waited for it for ever
                    cam.shown = None
                    cam.rviz_ready = False
                    self.shown_again += 1
                continue
            cam.rviz_ready = True
            due.append((cam, frame, intr))
        if due:
            self._start_batch(due, now)

    def _activate(self, cams):
        """Enable the RViz display of each camera somebody subscribes to (or did within
        KEEP_ACTIVE), disable the others (a disabled display is not rendered); the loop slows down
        when none is wanted."""
        wanted_any = False
        now = time.monotonic()
        for cam in cams:
            if cam.wanted():
                cam.wanted_at = now
            wanted = cam.wanted_at is not None and now - cam.wanted_at < KEEP_ACTIVE
            wanted_any = wanted_any or wanted
            if wanted == cam.active or (not wanted and cam.pending is not None):
                continue                # a frame in flight is finished first
            cam.active = wanted
            self.scene.set_active(cam.spec["id"], wanted)
            if wanted:
                cam.shown = None        # RViz forgot its CameraInfo: give it again
                cam.rviz_ready = False
        interval = TICK if wanted_any else IDLE_TICK
        if self.timer.interval() != interval:
            self.timer.setInterval(interval)

    def _start_batch(self, due, now):
        """Set RViz's scene time to T and send each camera's placeholder stamped T: RViz's Camera
        display moves its camera to the frame's pose at that stamp when the image arrives (and
        only then: a new placeholder per frame keeps a moving camera up to date)."""
        frames = sorted(set(frame for _cam, frame, _intr in due))
        stamp = self._batch_stamp(frames)
        if stamp is None:
            return
        if not stamp.is_zero() and not self._rviz_has_tf(stamp, now):
            return                              # next pass: RViz's tf listener is behind at T
        self.scene.sync_time(stamp.secs, stamp.nsecs)
        for cam, frame, intr in due:
            cam.blank.header.stamp = stamp      # zero when nothing moves: RViz takes the latest
            drawn = self.scene.drawn(cam.spec["id"])
            cam.pending = (self.scene.images_received(cam.spec["id"]), intr, frame,
                           drawn[0] if drawn is not None else None)
            cam.pub_blank.publish(cam.blank)
        self.batch = (stamp, now)
        self.batches += 1

    def _rviz_has_tf(self, stamp, now):
        """Whether RViz's own tf buffer has the batch's camera frames and the scene's frames at T
        (its listener thread can be behind this node's: a frame-locked object whose frame it cannot
        look up at T keeps its previous pose in the render, which the render's own report does not
        show). A batch waits for it up to 1 s, then goes ahead (counted in ``tf_waits_expired``)."""
        has = self.scene.rviz_has_tf(self.batch_frames, stamp.secs, stamp.nsecs)
        if has is not False:
            self.tf_wait_since = None
            return True
        if self.tf_wait_since is None:
            self.tf_wait_since = now
            self.tf_waits += 1
        if now - self.tf_wait_since < 1.0:
            return False
        self.tf_wait_since = None
        self.tf_waits_expired += 1
        rospy.logwarn_throttle(10.0, "RViz's tf did not reach the batch time within 1 s for %s; rendering "
                               "anyway (objects on those frames may be drawn at an older pose)"
                               % ", ".join(self.batch_frames[:6]))
        return True

    def _collect(self, cams, now):
        """Grab each camera of the batch once RViz has drawn it at T; the batch ends when all are
        grabbed (or after 1 s: dropped).

        With the ClipCamera plugin the render itself says what it showed: the stamp of the
        placeholder the camera took, the scene's time and whether the camera was at the frame's
        pose of that stamp; a camera is grabbed only when all three are T. Without it, once its
        placeholder count went up (RViz takes messages, updates its displays and renders in one
        pass of this thread's loop).

        RViz's tf listener runs in its own thread and can be behind this node's: a scene frame it
        does not have at T yet makes RViz move its time back to that frame's newest, and then its
        Camera displays keep their previous pose (they move only when an image comes in, and in
        exact sync only when its stamp is RViz's time). So when RViz's time moved it is set to T
        again, and a camera that took its placeholder but was not drawn at T gets it again."""
        stamp, since = self.batch
        t = (stamp.secs, stamp.nsecs)
        synced = stamp.is_zero() or self.scene.synced_time() in (None, t)
        if not synced:
            self.scene.sync_time(stamp.secs, stamp.nsecs)
            self.resyncs += 1
        waiting = False
        for cam in cams:
            if cam.pending is None:
                continue
            count, intr, frame, renders0 = cam.pending
            received = self.scene.images_received(cam.spec["id"])
            drawn = self.scene.drawn(cam.spec["id"])
            if drawn is not None and renders0 is not None:
                renders, image_stamp, scene_time, pose_ok = drawn
                good = (renders > renders0 and image_stamp == t and pose_ok
                        and (stamp.is_zero() or scene_time == t))
            else:
                good = received > count and synced
            if good:
                cam.pending = None
                rgb = self.scene.grab(cam.spec["id"])
                dep = self.scene.grab_depth(cam.spec["id"]) if cam.spec["depth"] else None
                if rgb is not None:
                    self._publish(cam, rgb, intr, frame, stamp if not stamp.is_zero() else rospy.Time.now(),
                                  dep)
                continue
            if now - since > 1.0:           # dropped (e.g. tf at T never reached RViz): start again
                cam.pending = None
                self.dropped += 1
                continue
            waiting = True
            if drawn is not None and renders0 is not None:
                # the camera shows its placeholder of T but was not drawn at T (it took it while
                # RViz's time was not T): send it again. (A placeholder still waiting in RViz's tf
                # filter for the camera frame at T shows an older stamp: wait for it.)
                retry = received > count and drawn[1] == t and drawn[0] > renders0
            else:
                retry = received > count and not synced
            if retry:
                cam.pending = (received, intr, frame, drawn[0] if drawn is not None else None)
                cam.pub_blank.publish(cam.blank)
                self.redraws += 1
        if not waiting:
            self.batch = None
            self.batch_time += now - since

    def _publish(self, cam, rgb, intr, frame, stamp, dep=None):
        spec = cam.spec
        if spec["lens"] is not None:
            if cam.lens_maps is None or cam.lens_maps[0] != intr:
                cam.lens_maps = (intr, lens.source_maps(intr, spec["lens"]))
            rgb = lens.apply(rgb, cam.lens_maps[1])
        rgb = camera_spec.apply_noise(rgb, spec["noise_mean"], spec["noise_stddev"], self.rng)
        if spec["trigger"]:
            with self.lock:
                cam.triggers = max(0, cam.triggers - 1)
        cam.last_rgb = rgb
        cam.frames += 1
        info_frame = cam.info.header.frame_id if cam.info is not None else ""
        header_frame = spec["header_frame"] or info_frame or frame
        if cam.pub_image.get_num_connections() > 0 or cam.recorder is not None:
            arr, encoding, step = camera_spec.convert(rgb, spec["format"])
            cam.pub_image.publish(_image(stamp, header_frame, arr, encoding, step))
        if cam.pub_info is not None:
            cam.pub_info.publish(self._out_info(cam, intr, stamp, header_frame))
        if dep is not None:
            self._publish_depth(cam, rgb, dep, intr, stamp, header_frame)
        with self.rec_lock:     # the recording services run in rospy's threads
            if cam.recorder is not None:
                try:
                    cam.recorder.write(rgb)
                except ConfigError as err:
                    rospy.logerr("camera '%s': recording stopped: %s", spec["name"], err)
                    cam.recorder = None

    def _publish_depth(self, cam, rgb, dep, intr, stamp, header_frame):
        """The depth image, its CameraInfo and the point cloud of one render (each only when
        someone subscribes to it)."""
        spec = cam.spec
        kept = depth.masked(dep, spec["point_cloud_cutoff"], spec["point_cloud_cutoff_max"])
        if cam.pub_depth is not None and cam.pub_depth.get_num_connections() > 0:
            arr, encoding, step = depth.depth_image(kept, spec["depth_format"])
            cam.pub_depth.publish(_image(stamp, header_frame, arr, encoding, step))
        if cam.pub_depth_info is not None and cam.pub_depth_info.get_num_connections() > 0:
            cam.pub_depth_info.publish(self._out_info(cam, intr, stamp, header_frame))
        if cam.pub_points is not None and cam.pub_points.get_num_connections() > 0:
            if cam.rays is None or cam.rays[0] != intr:
                cam.rays = (intr, depth.pixel_rays(intr.width, intr.height, intr.fx, intr.fy,
                                                   intr.cx, intr.cy))
            points, dense = depth.point_cloud(kept, rgb, cam.rays[1])
            msg = PointCloud2()
            msg.header.stamp, msg.header.frame_id = stamp, header_frame
            msg.height, msg.width = kept.shape
            msg.fields = [PointField(name, offset, PointField.FLOAT32, 1)
                          for name, offset in (("x", 0), ("y", 4), ("z", 8), ("rgb", 16))]
            msg.is_bigendian = False
            msg.point_step = depth.POINT_STEP
            msg.row_step = depth.POINT_STEP * msg.width
            msg.is_dense = dense
            msg.data = points.tobytes()
            cam.pub_points.publish(msg)

    # ---- services --------------------------------------------------------------------------------
    def _srv_save_frame(self, _req):
        saved, missing = [], []
        stamp = "%.3f" % rospy.Time.now().to_sec()
        with self.lock:
            cams = list(self.cams.values())
        for cam in cams:
            if cam.last_rgb is None:
                missing.append(cam.spec["name"])
                continue
            path = os.path.join(self.output_dir, "%s_%s.png" % (cam.spec["id"], stamp))
            try:
                saved.append(save_png(path, cam.last_rgb))
            except ConfigError as err:
                return TriggerResponse(False, str(err))
        text = " ".join(saved)
        if missing:
            text += (" " if text else "") + "(no frame yet: %s)" % ", ".join(missing)
        return TriggerResponse(bool(saved), text)

    def _start_recording(self, names=None):
        started = []
        with self.lock:
            cams = list(self.cams.values())
        for cam in cams:
            if names is not None and cam.spec["name"] not in names and cam.spec["id"] not in names:
                continue
            with self.rec_lock:
                if cam.recorder is None:
                    path = os.path.join(self.output_dir, "%s.avi" % cam.spec["id"])
                    cam.recorder = VideoRecorder(path, self.video_fps or cam.spec["rate"])
                started.append(cam.recorder.path)
        return started

    def _srv_start_recording(self, _req):
        try:
            started = self._start_recording()
        except ConfigError as err:
            return TriggerResponse(False, str(err))
        return TriggerResponse(bool(started), " ".join(started) or "no cameras")

    def _srv_stop_recording(self, _req):
        done = []
        with self.lock:
            cams = list(self.cams.values())
        for cam in cams:
            with self.rec_lock:         # not while the Qt thread writes a frame into it
                rec, cam.recorder = cam.recorder, None
                if rec is not None:
                    n = rec.close()
                    done.append("%s (%d frames)" % (rec.path, n))
        return TriggerResponse(bool(done), " ".join(done) or "nothing was recording")

    def close(self):
        print("camera_renderer: %d batches of frames (%.0f ms each on average, %d frames dropped, %d not "
              "drawn: nobody subscribed); "
              "RViz's time set to a batch's again %d times, placeholders sent again %d times (RViz's "
              "tf was behind); %d batches waited for RViz's tf to reach their time, %d of them 1 s and were "
              "drawn anyway; cameras given to RViz again %d times"
              % (self.batches, 1000.0 * self.batch_time / max(1, self.batches), self.dropped,
                 self.idle_frames, self.resyncs,
                 self.redraws, self.tf_waits, self.tf_waits_expired, self.shown_again), flush=True)
        self._on_shutdown()

    def _on_shutdown(self):
        with self.lock:
            cams = list(self.cams.values())
        for cam in cams:
            with self.rec_lock:
                rec, cam.recorder = cam.recorder, None
                if rec is not None:
                    rec.close()

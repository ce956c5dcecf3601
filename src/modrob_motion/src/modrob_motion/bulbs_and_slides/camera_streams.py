"""Camera streams of the demo: seed 000's principal views (top, front, right, orthographic) of the
running pick-and-place, rendered by ``rviz_camera_stream.launch`` (``sim:=false``: it joins the
demo's simulation; modrob_viz's camera_renderer), recorded to video, one frame saved by the
renderer's service. Checking the files (:func:`check_image`, :func:`check_video`) and the 2x2
mosaic (:func:`mosaic_video`) need no ROS.
"""
import os
import re
import shutil
import signal
import subprocess
import time

from modrob_motion.bulbs_and_slides import ScenarioError

VIEWS = ("topView", "frontView", "rightView", "orthoView")
RENDERER = "/camera_stream_renderer"


def launch_command(output_dir, width=320, height=240, f=200.0, rate=5.0):
    """``roslaunch`` of the four principal views only (no end-effector camera), recording them."""
    return ["roslaunch", "modrob_motion", "rviz_camera_stream.launch", "sim:=false", "ee_view:=false",
            "width:=%d" % width, "height:=%d" % height, "f:=%g" % f, "rate:=%g" % rate,
            "record:=%s" % ",".join(VIEWS), "output_dir:=%s" % os.path.abspath(output_dir)]


def check_image(path):
    """The image at ``path`` as a BGR array, or ScenarioError saying what is wrong with the file."""
    import cv2
    if not os.path.isfile(path) or os.path.getsize(path) == 0:
        raise ScenarioError("camera frame %s is missing or empty" % path)
    img = cv2.imread(path, cv2.IMREAD_COLOR)
    if img is None or img.size == 0:
        raise ScenarioError("camera frame %s cannot be decoded by OpenCV" % path)
    return img


def check_video(path, min_frames=2):
    """(frame count, first decoded frame, middle frame) of the video at ``path``; ScenarioError if
    it is missing, empty, undecodable or shorter than ``min_frames``."""
    import cv2
    if not os.path.isfile(path) or os.path.getsize(path) == 0:
        raise ScenarioError("camera video %s is missing or empty" % path)
    cap = cv2.VideoCapture(path)
    frames = []
    try:
        while True:
            ok, img = cap.read()
            if not ok:
                break
            frames.append(img)
    finally:
        cap.release()
    if len(frames) < min_frames:
        raise ScenarioError("camera video %s has %d decodable frames (need >= %d)"
                            % (path, len(frames), min_frames))
    return len(frames), frames[0], frames[len(frames) // 2]


def mosaic_video(paths, out_path, fps, labels=()):
    """The videos ``paths`` (up to 4, equal size) tiled 2x2 into one video, as long as the
    shortest, each tile captioned with its label; returns its frame count."""
    import cv2
    import numpy as np
    caps = [cv2.VideoCapture(p) for p in paths]
    writer = None
    n = 0
    try:
        while True:
            imgs = []
            for cap in caps:
                ok, img = cap.read()
                if not ok:
                    break
                imgs.append(img)
            if len(imgs) < len(caps) or not imgs:
                break
            h, w = imgs[0].shape[:2]
            imgs = [i if i.shape[:2] == (h, w) else cv2.resize(i, (w, h)) for i in imgs]
            for img, label in zip(imgs, labels):
                cv2.putText(img, label, (6, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
            while len(imgs) < 4:
                imgs.append(np.zeros_like(imgs[0]))
            tile = np.vstack([np.hstack(imgs[:2]), np.hstack(imgs[2:4])])
            if writer is None:
                writer = cv2.VideoWriter(out_path, cv2.VideoWriter_fourcc(*"MJPG"), float(fps),
                                         (tile.shape[1], tile.shape[0]), True)
                if not writer.isOpened():
                    raise ScenarioError("OpenCV cannot write the video %s" % out_path)
            writer.write(tile)
            n += 1
    finally:
        for cap in caps:
            cap.release()
        if writer is not None:
            writer.release()
    return n


def view_index(path):
    """Position of the file's view in VIEWS (tiling order of the mosaic); unknown views last."""
    name = os.path.basename(path)
    return next((i for i, v in enumerate(VIEWS) if name.startswith(v)), len(VIEWS))


def parse_recordings(text):
    """[(path, frames)] from the renderer's stop_recording reply ('<path> (<n> frames) ...')."""
    return [(m.group(1), int(m.group(2))) for m in re.finditer(r"(\S+) \((\d+) frames\)", text)]


class CameraStreams(object):
    """The renderer of the principal views beside the demo's simulation (ROS_MASTER_URI of this
    process). ``start`` launches it, ``wait_ready`` waits for the first image of every view,
    ``finish`` saves a frame, stops recording, stops the renderer and checks the files."""

    def __init__(self, out_dir, stem, rate=5.0, width=320, height=240, f=200.0):
        self.dir = os.path.abspath(out_dir)
        self.stem = stem
        self.views = VIEWS
        self.rate = rate
        self.cmd = launch_command(self.dir, width, height, f, rate)
        self.proc = None
        self.log = None
        self.log_path = None

    def start(self, log_path):
        try:
            import rospkg
            rospkg.RosPack().get_path("modrob_viz")
        except Exception:
            raise ScenarioError("camera streams need the modrob_viz package (camera_renderer); "
                                "build the workspace or run the demo with --no-streams")
        if os.path.isdir(self.dir):
            shutil.rmtree(self.dir)     # no stale frames or videos from an earlier run
        os.makedirs(self.dir)
        env = dict(os.environ)
        env.pop("DISPLAY", None)        # headless: the renderer starts its own Xvfb
        self.log_path = log_path
        self.log = open(log_path, "w")
        self.proc = subprocess.Popen(self.cmd, stdout=self.log, stderr=subprocess.STDOUT, env=env,
                                     start_new_session=True)

    def wait_ready(self, timeout=240.0):
        """Block until every view has published an image (the renderer and its X server are up)."""
        import rospy
        from sensor_msgs.msg import Image
        seen = set()
        subs = [rospy.Subscriber("/camera_%s/image" % v, Image, lambda _m, v=v: seen.add(v), queue_size=1)
                for v in VIEWS]
        deadline = time.time() + timeout
        try:
            while len(seen) < len(VIEWS):
                if self.proc.poll() is not None:
                    raise ScenarioError("the camera renderer exited (status %s): see %s"
                                        % (self.proc.returncode, self.log_path))
                if time.time() > deadline:
                    raise ScenarioError("no images from %s within %.0f s of wall time (the renderer is "
                                        "slow to start on a loaded machine; --no-streams skips it): see %s"
                                        % (", ".join(sorted(set(VIEWS) - seen)), timeout, self.log_path))
                time.sleep(0.2)
        finally:
            for s in subs:
                s.unregister()

    def _call(self, name, timeout=20.0):
        import rospy
        from std_srvs.srv import Trigger
        srv = RENDERER + "/" + name
        try:
            rospy.wait_for_service(srv, timeout)
            return rospy.ServiceProxy(srv, Trigger)()
        except (rospy.ROSException, rospy.ServiceException) as exc:
            raise ScenarioError("camera renderer service %s failed: %s (see %s)" % (srv, exc, self.log_path))

    def finish(self):
        """Save a frame of every view, stop recording, stop the renderer; write ``<stem>_frame.png``
        (the orthographic view) and ``<stem>_views.avi`` (the four views tiled); return the paths
        of every checked file. A renderer that does not answer its services (a loaded machine) is
        stopped all the same (it closes its videos on shutdown); the videos are then taken from its
        directory and the frame from the orthographic video. Only missing or undecodable files fail."""
        frames = []
        try:
            try:
                saved = self._call("save_frame")
                frames = [p for p in saved.message.split() if p.endswith(".png")] if saved.success else []
                if not frames:
                    self.warn("the camera renderer saved no frame (%s); taking one from the video"
                              % saved.message)
            except ScenarioError as err:
                self.warn("%s; taking the frame from the video" % err)
            try:
                stopped = self._call("stop_recording")
                if not parse_recordings(stopped.message):
                    self.warn("the camera renderer reported no video (%s)" % stopped.message)
            except ScenarioError as err:
                self.warn("%s; stopping the renderer closes its videos" % err)
        finally:
            self.stop()
        videos = [os.path.join(self.dir, "%s.avi" % v) for v in VIEWS]
        videos = [v for v in videos if os.path.isfile(v)]
        if not videos:
            raise ScenarioError("the camera renderer wrote no video in %s (see %s)"
                                % (self.dir, self.log_path))
        for path in videos:
            check_video(path)
        frame = self.stem + "_frame.png"
        ortho = [p for p in frames if os.path.basename(p).startswith("orthoView_")]
        for p in frames:
            check_image(p)
        if ortho:
            shutil.copyfile(ortho[0], frame)
        else:
            import cv2
            _n, _first, middle = check_video(videos[-1])
            if not cv2.imwrite(frame, middle):
                raise ScenarioError("cannot write %s" % frame)
        check_image(frame)
        mosaic = self.stem + "_views.avi"
        mosaic_video(videos, mosaic, self.rate, [os.path.splitext(os.path.basename(v))[0] for v in videos])
        check_video(mosaic)
        return [mosaic, frame] + frames + videos

    def warn(self, text):
        print("bulbs_and_slides_demo: camera streams: %s" % text, flush=True)

    def stop(self):
        if self.proc is not None and self.proc.poll() is None:
            try:
                os.killpg(self.proc.pid, signal.SIGINT)
                self.proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
        if self.log is not None:
            self.log.close()
            self.log = None

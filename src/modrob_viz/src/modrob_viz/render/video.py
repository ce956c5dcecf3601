"""Image files and videos of camera streams (OpenCV; no rospy)."""
import os

import cv2

from modrob_viz.errors import ConfigError

FOURCC = {".avi": "MJPG", ".mp4": "mp4v", ".mkv": "MJPG"}


def save_png(path, rgb):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    if not cv2.imwrite(path, rgb[:, :, ::-1] if rgb.ndim == 3 else rgb):
        raise ConfigError("could not write %s (directory writable? extension .png/.jpg?)" % path)
    return path


class VideoRecorder(object):
    """Frames (RGB or mono uint8, all of one size) to a video file at ``fps``."""

    def __init__(self, path, fps):
        ext = os.path.splitext(path)[1].lower()
        if ext not in FOURCC:
            raise ConfigError("video file %s: use .avi (MJPG), .mp4 (mp4v) or .mkv" % path)
        if not fps > 0:
            raise ConfigError("video fps must be > 0, got %r" % (fps,))
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        self.path, self.fps, self._fourcc = path, float(fps), cv2.VideoWriter_fourcc(*FOURCC[ext])
        self._writer = None
        self._size = None
        self.frames = 0

    def write(self, rgb):
        h, w = rgb.shape[:2]
        if self._writer is None:
            self._size = (w, h)
            self._writer = cv2.VideoWriter(self.path, self._fourcc, self.fps, self._size, True)
            if not self._writer.isOpened():
                raise ConfigError("OpenCV cannot open a video writer for %s" % self.path)
        if (w, h) != self._size:
            rgb = cv2.resize(rgb, self._size)
        bgr = cv2.cvtColor(rgb, cv2.COLOR_GRAY2BGR) if rgb.ndim == 2 else rgb[:, :, ::-1]
        self._writer.write(bgr)
        self.frames += 1

    def close(self):
        if self._writer is not None:
            self._writer.release()
            self._writer = None
        return self.frames

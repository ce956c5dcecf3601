#!/usr/bin/env python3
"""rostest: web_video_server's URLs over real HTTP, and a real headless browser showing the stream."""
import os
import shutil
import subprocess
import tempfile
import time
import unittest
import urllib.request

import cv2
import numpy as np
import rospkg
import rospy
import rostest

TOPIC = "/test_cam/image_raw"


def red_pixels(bgr):
    b, g, r = bgr[..., 0].astype(int), bgr[..., 1].astype(int), bgr[..., 2].astype(int)
    return int(np.count_nonzero((r > 100) & (g < 70) & (b < 70)))


class WebVideoServer(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        end = time.monotonic() + 60
        while not rospy.has_param("/web_video_server/bound_port") and time.monotonic() < end:
            time.sleep(0.2)
        cls.base = "http://127.0.0.1:%d" % rospy.get_param("/web_video_server/bound_port")
        rospy.wait_for_message(TOPIC, rospy.AnyMsg, timeout=120)

    def get(self, path, timeout=30):
        return urllib.request.urlopen(self.base + path, timeout=timeout)

    def test_1_index_lists_the_image_topic(self):
        page = self.get("/").read().decode()
        self.assertIn("/stream_viewer?topic=%s" % TOPIC, page)
        self.assertIn("/snapshot?topic=%s" % TOPIC, page)

    def test_2_snapshot_is_a_jpeg_of_the_camera(self):
        r = self.get("/snapshot?topic=%s" % TOPIC)
        self.assertEqual(r.headers["Content-Type"], "image/jpeg")
        img = cv2.imdecode(np.frombuffer(r.read(), np.uint8), cv2.IMREAD_COLOR)
        self.assertEqual(img.shape[:2], (240, 320))
        self.assertGreater(red_pixels(img), 300, "the snapshot does not show the red box")
        small = self.get("/snapshot?topic=%s&width=160" % TOPIC).read()
        small = cv2.imdecode(np.frombuffer(small, np.uint8), 1)
        self.assertEqual(small.shape[:2], (120, 160))

    def test_3_mjpeg_stream_delivers_frames(self):
        r = self.get("/stream?topic=%s" % TOPIC)
        self.assertTrue(r.headers["Content-Type"].startswith("multipart/x-mixed-replace"))
        data = b""
        end = time.monotonic() + 30
        while data.count(b"\xff\xd9") < 3 and time.monotonic() < end:
            data += r.read1(65536)
        r.close()
        self.assertGreaterEqual(data.count(b"Content-Type: image/jpeg"), 3,
                                "fewer than 3 MJPEG parts in 30 s")

    def test_4_errors_name_the_problem(self):
        with self.assertRaises(urllib.error.HTTPError) as ctx:
            self.get("/snapshot?topic=/no_such_image", timeout=30)
        self.assertEqual(ctx.exception.code, 404)
        self.assertIn("/no_such_image", ctx.exception.read().decode())
        for path, words in (("/stream", "give the image topic: /stream?topic="),
                            ("/snapshot?topic=%s&quality=high" % TOPIC, "must be integers"),
                            ("/stream?topic=%s&type=vp8" % TOPIC, "use type=mjpeg"),
                            ("/nowhere", "try / for the list")):
            with self.assertRaises(urllib.error.HTTPError) as ctx:
                self.get(path, timeout=30)
            self.assertEqual(ctx.exception.code, 404 if path == "/nowhere" else 400, path)
            self.assertIn(words, ctx.exception.read().decode(), path)

    def test_5_headless_chromium_shows_the_stream(self):
        browser = shutil.which("chromium") or shutil.which("chromium-browser")
        self.assertIsNotNone(browser, "Debian's chromium is not installed (scripts/debian-packages.txt)")
        tmp = tempfile.mkdtemp(prefix="wvs_")            # the browser profiles
        self.addCleanup(shutil.rmtree, tmp, ignore_errors=True)
        # the screenshot stays, for a person to look at, with the other tests' outputs
        shot = os.path.join(rospkg.get_ros_home(), "test_output", "web_video_server_viewer.png")
        os.makedirs(os.path.dirname(shot), exist_ok=True)
        cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
               "--user-data-dir=" + os.path.join(tmp, "profile"), "--window-size=480,400",
               "--virtual-time-budget=8000", "--screenshot=" + shot,
               self.base + "/stream_viewer?topic=%s" % TOPIC]
        subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=120)
        self.assertTrue(os.path.exists(shot), "chromium wrote no screenshot")
        img = cv2.imread(shot)
        self.assertGreater(red_pixels(img), 300, "the browser does not show the camera's red box (%s)" % shot)
        dom = subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu",
                              "--user-data-dir=" + os.path.join(tmp, "profile2"), "--dump-dom",
                              self.base + "/"],
                             stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, timeout=120).stdout.decode()
        self.assertIn(TOPIC, dom)


if __name__ == "__main__":
    rospy.init_node("check_web_video_server")
    rostest.rosrun("web_video_server", "check_web_video_server", WebVideoServer)

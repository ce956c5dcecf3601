#!/usr/bin/env python3
"""rostest: RViz, run headless on its own Xvfb with config/joint_trajectory.rviz, draws the red
end-effector path and the blue robot (pixels counted in a grab of the screen)."""
import os
import random
import subprocess
import time
import unittest

import numpy as np
import rospy
import rostest
from visualization_msgs.msg import Marker

from viz_test_utils import wait_for


def free_display():
    for n in random.sample(range(100, 900), 800):
        if not os.path.exists("/tmp/.X11-unix/X%d" % n) and not os.path.exists("/tmp/.X%d-lock" % n):
            return n
    raise RuntimeError("no free X display number")


def grab(app_screen):
    img = app_screen.grabWindow(0).toImage().convertToFormat(4)  # QImage.Format_RGB32
    ptr = img.bits()
    ptr.setsize(img.byteCount())
    arr = np.frombuffer(ptr, np.uint8).reshape(img.height(), img.bytesPerLine() // 4, 4)
    return arr[:, :img.width(), 2::-1].astype(int)  # BGRA -> RGB


class RvizRender(unittest.TestCase):
    def test_path_and_robot_are_drawn(self):
        self.assertIsNotNone(wait_for("/joint_trajectory_visualizer/marker", Marker,
                                      lambda m: len(m.points) > 1000, 40), "no path to draw")
        n = free_display()
        xvfb = subprocess.Popen(["Xvfb", ":%d" % n, "-screen", "0", "1280x1024x24"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        env = dict(os.environ, DISPLAY=":%d" % n)
        rviz = None
        try:
            deadline = time.time() + 10
            while not os.path.exists("/tmp/.X11-unix/X%d" % n) and time.time() < deadline:
                time.sleep(0.1)
            rviz = subprocess.Popen(["rviz", "-d", rospy.get_param("~config")], env=env,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            os.environ["DISPLAY"] = ":%d" % n
            from PyQt5.QtWidgets import QApplication
            app = QApplication(["check_rviz_render"])
            red = blue = 0
            deadline = time.time() + 45
            while time.time() < deadline:
                time.sleep(1.0)
                px = grab(app.primaryScreen())
                r, g, b = px[..., 0], px[..., 1], px[..., 2]
                red = int(np.count_nonzero((r > 180) & (g < 70) & (b < 70)))
                blue = int(np.count_nonzero((b > 150) & (r < 60) & (g < 90)))
                if red > 300 and blue > 2000:
                    break
            self.assertGreater(red, 300, "RViz shows no red end-effector path (%d red pixels)" % red)
            self.assertGreater(blue, 2000, "RViz shows no blue robot joints (%d blue pixels)" % blue)
        finally:
            if rviz is not None:
                rviz.terminate()
                try:
                    rviz.wait(10)
                except subprocess.TimeoutExpired:
                    rviz.kill()
            xvfb.terminate()
            xvfb.wait(10)


if __name__ == "__main__":
    rospy.init_node("check_rviz_render")
    rostest.rosrun("modrob_viz", "check_rviz_render", RvizRender)

#!/usr/bin/env python3
"""rostest node for reconfigure_gui.test: the reconfigure window, under its own Xvfb, lists the
PTRZ controllers' pid servers; dragging pan's p slider to 400 changes the controller's gain (read
back through dynamic_reconfigure's client, in the controller's state topic, and as a faster step
response); a change made elsewhere shows in the window; a bad value typed is refused with a
message. Saves a screenshot to ~screenshot_dir (default $ROS_HOME/test_output)."""
import os
import sys
import time
import unittest

import rospkg
import rospy
import rostest
from dynamic_reconfigure.client import Client
from modrob_viz.render.xvfb import Xvfb

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from step_response import StepProbe, measure_rise  # noqa: E402

CTRL = "/ptrz/pan_position_controller"
SERVER = CTRL + "/pid"


class ReconfigureGui(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("reconfigure_gui_check")
        cls.xvfb = Xvfb(1280, 1024).__enter__()
        from PyQt5 import QtWidgets
        from rqt_reconfigure.main_window import ReconfigureWindow
        from rqt_reconfigure.ros_servers import ServerConnection, list_servers
        cls.app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(["reconfigure_gui_check"])
        cls.window = ReconfigureWindow(list_servers, ServerConnection, refresh_period=0)
        cls.window.show()
        cls.probe = StepProbe(CTRL)
        rospy.wait_for_service(SERVER + "/set_parameters", timeout=60)
        cls.wait(lambda: cls.probe.latest() is not None, 60, "pan controller state")

    @classmethod
    def tearDownClass(cls):
        cls.window.close()
        cls.xvfb.__exit__()

    @classmethod
    def wait(cls, pred, timeout, what):
        deadline = time.monotonic() + timeout
        while not pred():
            cls.app.processEvents()
            if time.monotonic() > deadline or rospy.is_shutdown():
                raise AssertionError("timed out after %.0f s waiting for %s" % (timeout, what))
            time.sleep(0.01)

    def screenshot(self, name):
        path = rospy.get_param("~screenshot_dir", os.path.join(rospkg.get_ros_home(), "test_output"))
        os.makedirs(path, exist_ok=True)
        out = os.path.join(path, name)
        self.app.processEvents()
        self.assertTrue(self.window.grab().save(out), "could not save %s" % out)
        rospy.loginfo("screenshot: %s", out)

    def panel(self):
        return self.window.panels[SERVER]

    def test_1_lists_the_pid_servers_and_filters(self):
        self.wait(lambda: (self.window.refresh() or True) and SERVER in self.window.server_items(), 30,
                  "%s in the tree" % SERVER)
        items = self.window.server_items()
        for c in ("pan", "tilt", "roll"):
            self.assertIn("/ptrz/%s_position_controller/pid" % c, items)
        self.window.filter.setText("tilt")
        self.assertTrue(items["/ptrz/tilt_position_controller/pid"].isHidden() is False)
        self.assertTrue(items[SERVER].isHidden())
        self.window.filter.setText("")
        self.assertFalse(items[SERVER].isHidden())

    def test_2_slider_changes_the_gain_and_the_step_response(self):
        rise_slow, slow = measure_rise(self.probe, 0.0, 1.0, 3.0, self.app.processEvents)
        self.assertEqual(slow[-1].p, 100.0)
        self.probe.step(0.0, 3.0, self.app.processEvents)

        item = self.window.server_items()[SERVER]
        self.window._item_clicked(item, 0)               # what a click on the tree item does
        self.wait(lambda: "p" in self.panel().editors and self.panel().editors["p"].edit.text() == "100",
                  30, "the pid panel showing p = 100")
        self.screenshot("rqt_reconfigure_gui_before.png")
        editor = self.panel().editors["p"]
        slider = editor.slider
        slider.setSliderDown(True)                        # a drag: press, move, release
        slider.setSliderPosition(editor.spec.to_ticks(400.0))
        self.assertEqual(editor.edit.text(), "400")       # shown while dragging ...
        slider.setSliderDown(False)                       # ... sent on release
        client = Client(SERVER, timeout=20)
        self.wait(lambda: client.get_configuration(timeout=5)["p"] == 400.0, 30, "p = 400 at the server")
        self.wait(lambda: self.probe.latest().p == 400.0, 30, "p = 400 in the controller state")
        rise_fast, fast = measure_rise(self.probe, 0.0, 1.0, 3.0, self.app.processEvents)
        rospy.loginfo("pan 1 rad step: rise time %.3f s with p = 100, %.3f s with p = 400",
                      rise_slow, rise_fast)
        self.assertLess(rise_fast, 0.8 * rise_slow)
        self.assertLess(abs(fast[-1].process_value - 1.0), 0.05)

    def test_3_follows_changes_made_elsewhere(self):
        self.window.open_server(SERVER)
        client = Client(SERVER, timeout=20)
        client.update_configuration({"d": 25.0})
        self.wait(lambda: self.panel().editors["d"].edit.text() == "25", 30, "d = 25 shown in the window")
        d = self.panel().editors["d"]
        self.assertEqual(d.slider.value(), d.spec.to_ticks(25.0))
        self.screenshot("rqt_reconfigure_gui.png")

    def test_4_bad_value_is_refused_with_a_message(self):
        self.window.open_server(SERVER)
        editor = self.panel().editors["i"]
        before = editor.edit.text()
        editor.edit.setText("nan")
        editor.edit.editingFinished.emit()
        self.assertIn("'nan' is not a finite double for parameter 'i'", self.window.status.text())
        self.assertEqual(editor.edit.text(), before)
        editor.edit.setText("1e9")
        editor.edit.editingFinished.emit()
        self.assertIn("outside", self.window.status.text())


if __name__ == "__main__":
    rostest.rosrun("rqt_reconfigure", "reconfigure_gui_check", ReconfigureGui)

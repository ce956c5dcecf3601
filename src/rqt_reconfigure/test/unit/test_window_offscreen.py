"""Tier 1: the reconfigure window with Qt's offscreen platform and a fake server (no master):
every editor kind (double and int sliders, bool, enum, string, a nested group) is built from a
description, sends what the user does, follows updates, and a server that disappears closes.
The offscreen platform is chosen for this QApplication only (``-platform offscreen``), not
through the environment; tests that need a real display are rostests with their own Xvfb."""
import pytest
from PyQt5 import QtCore, QtWidgets

from rqt_reconfigure.main_window import ReconfigureWindow
from rqt_reconfigure.param_model import group_from_dict

ENUM = ("{'enum': [{'name': 'Low', 'type': 'int', 'value': 0, 'description': 'slow'}, "
        "{'name': 'High', 'type': 'int', 'value': 1, 'description': 'fast'}], 'enum_description': 'speed'}")
DESCRIPTION = {"name": "Default", "type": "", "groups": {
    "camera": {"name": "camera", "type": "", "groups": {}, "parameters": [
        {"name": "frame_id", "type": "str", "default": "cam", "edit_method": ""}]}},
    "parameters": [
        {"name": "gain", "type": "double", "min": 0.0, "max": 10.0, "default": 1.0, "edit_method": ""},
        {"name": "count", "type": "int", "min": 0, "max": 20, "default": 3, "edit_method": ""},
        {"name": "enabled", "type": "bool", "min": False, "max": True, "default": True, "edit_method": ""},
        {"name": "speed", "type": "int", "min": 0, "max": 1, "default": 0, "edit_method": ENUM}]}
CONFIG = {"gain": 1.0, "count": 3, "enabled": True, "speed": 0, "frame_id": "cam"}


class FakeServer(object):
    def __init__(self, name, on_description, on_config, on_error):
        self.name = name
        self.sent = []
        self.closed = False
        self.on_config = on_config
        on_description(group_from_dict(DESCRIPTION))
        on_config(dict(CONFIG))

    def set(self, changes):
        self.sent.append(dict(changes))

    def close(self):
        self.closed = True


@pytest.fixture
def window():
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(["test", "-platform", "offscreen"])
    servers = {"names": ["/cam/driver", "/ptrz/pan_position_controller/pid"]}
    made = {}

    def connect(name, on_description, on_config, on_error):
        made[name] = FakeServer(name, on_description, on_config, on_error)
        return made[name]

    w = ReconfigureWindow(lambda: list(servers["names"]), connect, refresh_period=0)
    w.refresh()
    w.show()
    yield w, made, servers, app
    w.close()


def test_every_editor_kind_sends_and_follows(window):
    w, made, _servers, app = window
    items = w.server_items()
    assert sorted(items) == ["/cam/driver", "/ptrz/pan_position_controller/pid"]
    items["/cam/driver"].setCheckState(0, QtCore.Qt.Checked)         # ticking the box opens it
    app.processEvents()
    panel = w.panels["/cam/driver"]
    ed = panel.editors
    assert set(ed) == {"gain", "count", "enabled", "speed", "frame_id"}
    assert ed["gain"].edit.text() == "1" and ed["count"].slider.value() == 3
    assert ed["enabled"].box.isChecked() and ed["speed"].combo.currentText() == "Low (0)"
    fake = made["/cam/driver"]

    ed["gain"].slider.setValue(ed["gain"].spec.to_ticks(2.5))          # keyboard/wheel step: sent at once
    ed["count"].slider.setValue(7)
    ed["enabled"].box.setChecked(False)
    ed["speed"].combo.setCurrentIndex(1)
    ed["frame_id"].edit.setText("cam2")
    ed["frame_id"].edit.editingFinished.emit()
    assert fake.sent == [{"gain": 2.5}, {"count": 7}, {"enabled": False}, {"speed": 1}, {"frame_id": "cam2"}]

    fake.on_config(dict(CONFIG, gain=7.0, speed=1))                    # an update made elsewhere
    app.processEvents()
    assert ed["gain"].edit.text() == "7" and ed["gain"].slider.value() == ed["gain"].spec.to_ticks(7.0)
    assert ed["speed"].combo.currentText() == "High (1)"
    assert len(fake.sent) == 5                                         # following sends nothing back
    assert "/cam/driver: frame_id = cam2" in w.status.text()


def test_filter_hides_and_a_vanished_server_closes(window):
    w, made, servers, app = window
    w.filter.setText("pan")
    items = w.server_items()
    assert items["/cam/driver"].isHidden() and not items["/ptrz/pan_position_controller/pid"].isHidden()
    w.filter.setText("")
    w.open_server("/cam/driver")
    servers["names"] = ["/ptrz/pan_position_controller/pid"]
    w.refresh()
    assert "/cam/driver" not in w.panels and made["/cam/driver"].closed
    assert w.status.text() == "/cam/driver went away"
    assert list(w.server_items()) == ["/ptrz/pan_position_controller/pid"]

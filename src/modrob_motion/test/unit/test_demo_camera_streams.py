"""Tier 1: the demo's camera streams (make demo writes a frame and a video of the principal views).

The wiring to modrob_viz (launch arguments, renderer services and their reply format), the file
checks on real PNG/AVI files (missing, empty, undecodable, too short), the 2x2 mosaic, and the
demo runner's order (renderer up before the pick-and-place, files checked after it, failure when
they are missing) without a simulator.
"""
import os
import re
import xml.etree.ElementTree as ET

import cv2
import numpy as np
import pytest

from modrob_motion.bulbs_and_slides import ScenarioError, camera_streams, demo

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
VIZ = os.path.join(SRC, "modrob_viz")
MOTION = os.path.join(SRC, "modrob_motion")


def _video(path, n, size=(64, 48), colour=(0, 0, 255)):
    w = cv2.VideoWriter(path, cv2.VideoWriter_fourcc(*"MJPG"), 5.0, size, True)
    for i in range(n):
        img = np.full((size[1], size[0], 3), colour, np.uint8)
        img[:, : (i * 3) % size[0]] = 255
        w.write(img)
    w.release()
    return path


def test_launch_command_uses_arguments_the_launch_file_declares():
    cmd = camera_streams.launch_command("out/x", 320, 240, 200.0, 5.0)
    assert cmd[:3] == ["roslaunch", "modrob_motion", "rviz_camera_stream.launch"]
    given = dict(a.split(":=", 1) for a in cmd[3:])
    launch = ET.parse(os.path.join(MOTION, "launch", "rviz_camera_stream.launch")).getroot()
    declared = {a.get("name") for a in launch.iter("arg")}
    assert set(given) <= declared, "not declared by rviz_camera_stream.launch: %s" % (set(given) - declared)
    assert given["sim"] == "false" and given["ee_view"] == "false"
    assert given["record"].split(",") == list(camera_streams.VIEWS)
    assert os.path.isabs(given["output_dir"])
    names = {n.get("name") for n in launch.iter("node") if n.get("type") == "camera_renderer"}
    assert camera_streams.RENDERER.lstrip("/") in names
    cams = " ".join(r.text for r in launch.iter("rosparam") if r.get("unless") == "$(arg ee_view)")
    for view in camera_streams.VIEWS:    # the four views, each named and on /camera_<view>/image
        assert "name: %s," % view in cams and "image: /camera_%s/image," % view in cams
    assert "eeView" not in cams


def test_renderer_services_and_reply_format_match():
    with open(os.path.join(VIZ, "src", "modrob_viz", "render", "node.py")) as f:
        node = f.read()
    for srv in ("save_frame", "stop_recording"):
        assert 'rospy.Service("~%s"' % srv in node
    assert '"%s (%d frames)" % (rec.path, n)' in node
    text = "/o/topView.avi (12 frames) /o/orthoView.avi (3 frames)"
    assert camera_streams.parse_recordings(text) == [("/o/topView.avi", 12), ("/o/orthoView.avi", 3)]
    assert camera_streams.parse_recordings("nothing was recording") == []
    assert re.search(r'"%s_%s\.png" % \(cam\.spec\["id"\], stamp\)', node)   # frames: <view>_<stamp>.png


def test_check_image(tmp_path):
    good = str(tmp_path / "a.png")
    cv2.imwrite(good, np.zeros((8, 8, 3), np.uint8))
    assert camera_streams.check_image(good).shape == (8, 8, 3)
    empty = tmp_path / "e.png"
    empty.write_bytes(b"")
    junk = tmp_path / "j.png"
    junk.write_bytes(b"not a png at all")
    for bad, why in ((str(tmp_path / "missing.png"), "missing or empty"), (str(empty), "missing or empty"),
                     (str(junk), "cannot be decoded")):
        with pytest.raises(ScenarioError, match=why):
            camera_streams.check_image(bad)


def test_check_video(tmp_path):
    n, first, middle = camera_streams.check_video(_video(str(tmp_path / "v.avi"), 7))
    assert n == 7 and first.shape == (48, 64, 3) and middle.shape == first.shape
    with pytest.raises(ScenarioError, match="1 decodable frames"):
        camera_streams.check_video(_video(str(tmp_path / "short.avi"), 1))
    junk = tmp_path / "j.avi"
    junk.write_bytes(b"\0" * 1000)
    with pytest.raises(ScenarioError, match="0 decodable frames"):
        camera_streams.check_video(str(junk))
    with pytest.raises(ScenarioError, match="missing or empty"):
        camera_streams.check_video(str(tmp_path / "none.avi"))


def test_mosaic_tiles_the_views_2x2_as_long_as_the_shortest(tmp_path):
    colours = [(255, 0, 0), (0, 255, 0), (0, 0, 255), (0, 255, 255)]
    paths = [_video(str(tmp_path / ("%s.avi" % v)), 6 - i, colour=c)
             for i, (v, c) in enumerate(zip(camera_streams.VIEWS, colours))]
    out = str(tmp_path / "views.avi")
    assert camera_streams.mosaic_video(paths, out, 5.0, camera_streams.VIEWS) == 3
    n, first, _ = camera_streams.check_video(out)
    assert n == 3 and first.shape == (96, 128, 3)
    for (r, c), colour in zip(((40, 50), (40, 114), (88, 50), (88, 114)), colours):
        assert np.abs(first[r, c].astype(int) - colour).max() < 60      # each view in its tile
    assert [camera_streams.view_index(p) for p in reversed(paths)] == [3, 2, 1, 0]


def _finish(tmp_path, monkeypatch, answers):
    """CameraStreams.finish on videos already in its directory, the services answering ``answers``
    (name -> Trigger-like reply, or an exception to raise)."""
    streams = camera_streams.CameraStreams(str(tmp_path / "cam"), str(tmp_path / "demo"))
    os.makedirs(streams.dir)
    for i, view in enumerate(camera_streams.VIEWS):
        _video(os.path.join(streams.dir, view + ".avi"), 5 + i)
    calls = []

    def call(name, timeout=20.0):
        calls.append(name)
        answer = answers[name]
        if isinstance(answer, Exception):
            raise answer
        return answer
    monkeypatch.setattr(streams, "_call", call)
    monkeypatch.setattr(streams, "stop", lambda: calls.append("stop"))
    return streams, calls


class _Reply(object):
    def __init__(self, success, message):
        self.success, self.message = success, message


def test_finish_with_answering_renderer(tmp_path, monkeypatch):
    png = str(tmp_path / "cam" / "orthoView_12.000.png")
    answers = {"save_frame": _Reply(True, png),
               "stop_recording": _Reply(True, "%s/topView.avi (5 frames)" % (tmp_path / "cam"))}
    streams, calls = _finish(tmp_path, monkeypatch, answers)
    cv2.imwrite(png, np.zeros((48, 64, 3), np.uint8))
    paths = streams.finish()
    assert calls == ["save_frame", "stop_recording", "stop"]
    assert paths[:2] == [str(tmp_path / "demo_views.avi"), str(tmp_path / "demo_frame.png")]
    assert camera_streams.check_video(paths[0])[0] == 5     # the shortest view
    assert camera_streams.check_image(paths[1]).shape == (48, 64, 3)


def test_finish_when_the_renderer_does_not_answer(tmp_path, monkeypatch, capsys):
    """A loaded machine: the services fail (transport error); the renderer is stopped anyway and
    the files it wrote are used, the frame taken from the orthographic video."""
    err = ScenarioError("camera renderer service /camera_stream_renderer/stop_recording failed: "
                        "transport error")
    streams, calls = _finish(tmp_path, monkeypatch, {"save_frame": err, "stop_recording": err})
    paths = streams.finish()
    assert calls == ["save_frame", "stop_recording", "stop"]
    assert camera_streams.check_image(str(tmp_path / "demo_frame.png")).shape == (48, 64, 3)
    assert camera_streams.check_video(paths[0])[0] == 5
    assert "taking the frame from the video" in capsys.readouterr().out


def test_finish_fails_without_videos(tmp_path, monkeypatch):
    streams, _ = _finish(tmp_path, monkeypatch, {"save_frame": _Reply(False, "no frame yet"),
                                                 "stop_recording": _Reply(False, "nothing was recording")})
    for view in camera_streams.VIEWS:
        os.remove(os.path.join(streams.dir, view + ".avi"))
    streams.log_path = "x.log"
    with pytest.raises(ScenarioError, match="wrote no video"):
        streams.finish()


class _Streams(object):
    def __init__(self, calls, fail=None):
        self.calls, self.fail, self.views = calls, fail, camera_streams.VIEWS

    def start(self, log):
        self.calls.append("start")

    def wait_ready(self):
        self.calls.append("wait_ready")

    def finish(self):
        self.calls.append("finish")
        if self.fail:
            raise ScenarioError(self.fail)
        return ["/o/views.avi", "/o/frame.png"]

    def stop(self):
        self.calls.append("stop")


class _Result(object):
    success = True

    def as_dict(self):
        return {"success": True}

    def line(self, scenario):
        return "RESULT %s: SUCCESS" % scenario


def _run(monkeypatch, tmp_path, capsys, argv, fail=None):
    calls = []
    monkeypatch.setattr(demo, "start_simulation", lambda *a, **k: (None, None))
    monkeypatch.setattr(demo, "stop_simulation", lambda *a: calls.append("stop_simulation"))
    monkeypatch.setattr(demo, "wait_for_master", lambda: True)
    monkeypatch.setattr(demo, "wait_for_param", lambda name: True)
    monkeypatch.setattr(demo, "make_streams", lambda args, stem: _Streams(calls, fail))
    import rospy
    from modrob_motion.bulbs_and_slides import scenario
    monkeypatch.setattr(rospy, "init_node", lambda *a, **k: None)

    class FakeScenario(object):
        def __init__(self, *a, **k):
            self.recorder = None

        def run_one_robot(self):
            calls.append("scenario")
            return _Result()

        def stream_stats(self, result):
            pass

    monkeypatch.setattr(scenario, "Scenario", FakeScenario)
    code = demo.main(["--out", str(tmp_path)] + argv)
    return code, calls, capsys.readouterr().out


def test_demo_renders_before_the_scenario_and_checks_files_after(monkeypatch, tmp_path, capsys):
    code, calls, out = _run(monkeypatch, tmp_path, capsys, [])
    assert code == 0
    assert calls == ["start", "wait_ready", "scenario", "finish", "stop", "stop_simulation"]
    assert "wrote /o/views.avi" in out and "wrote /o/frame.png" in out


def test_demo_fails_when_the_stream_files_are_missing(monkeypatch, tmp_path, capsys):
    code, calls, out = _run(monkeypatch, tmp_path, capsys, [], fail="camera video x is missing or empty")
    assert code == 1 and "FAILURE -- the camera streams" in out
    assert calls[-2:] == ["stop", "stop_simulation"]


def test_demo_without_streams(monkeypatch, tmp_path, capsys):
    code, calls, _ = _run(monkeypatch, tmp_path, capsys, ["--no-streams"])
    assert code == 0 and calls == ["scenario", "stop_simulation"]


def test_demo_writes_the_bag_and_plots_while_the_simulation_stops(monkeypatch, tmp_path, capsys):
    # roslaunch's teardown takes 2-3 s of wall time; the bag and the plots need no simulation
    import threading
    from modrob_motion.bulbs_and_slides import scenario
    stopping, written = threading.Event(), threading.Event()
    seen = {}

    def stop_simulation(*a):
        stopping.set()
        seen["written while stopping"] = written.wait(10.0)

    class Recorder(object):
        rows = {"modrob0": [1]}

        def write_bag(self, path):
            seen["stopping while writing"] = stopping.wait(10.0)
            written.set()
            return 1

        def plot_joints(self, *a, **k):
            pass

    class FakeScenario(object):
        def __init__(self, *a, **k):
            self.recorder, self.robots = Recorder(), {}

        def run_one_robot(self):
            return _Result()

        def stream_stats(self, result):
            pass
    monkeypatch.setattr(demo, "start_simulation", lambda *a, **k: (None, None))
    monkeypatch.setattr(demo, "stop_simulation", stop_simulation)
    monkeypatch.setattr(demo, "wait_for_master", lambda: True)
    monkeypatch.setattr(demo, "wait_for_param", lambda name: True)
    import rospy
    monkeypatch.setattr(rospy, "init_node", lambda *a, **k: None)
    monkeypatch.setattr(scenario, "Scenario", FakeScenario)
    assert demo.main(["--out", str(tmp_path), "--no-streams"]) == 0
    assert seen == {"stopping while writing": True, "written while stopping": True}
    assert "RESULT one_robot: SUCCESS" in capsys.readouterr().out


def test_make_streams_size_and_focal_length(tmp_path):
    args = demo.main.__globals__["argparse"].Namespace(stream_size="640x480", stream_rate=4.0)
    s = demo.make_streams(args, str(tmp_path / "x"))
    given = dict(a.split(":=", 1) for a in s.cmd[3:])
    assert (given["width"], given["height"], given["f"], given["rate"]) == ("640", "480", "400", "4")
    with pytest.raises(SystemExit, match="WIDTHxHEIGHT"):
        demo.make_streams(args.__class__(stream_size="big", stream_rate=4.0), "x")

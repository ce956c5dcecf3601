"""Tier 1: rqt_plot's series names, field checks against real message classes, the store, CSV
round trip and the PNG (no master)."""
import math

import pytest
from control_msgs.msg import JointControllerState
from geometry_msgs.msg import Pose, PoseStamped
from sensor_msgs.msg import JointState

from rqt_plot.errors import PlotError
from rqt_plot.field_path import check_path, expand, extract, parse_fields, split_topic
from rqt_plot.series import SeriesStore, read_csv, write_csv, write_png

CLASSES = {"geometry_msgs/Pose": Pose, "geometry_msgs/Point": __import__("geometry_msgs.msg").msg.Point,
           "geometry_msgs/Quaternion": __import__("geometry_msgs.msg").msg.Quaternion,
           "std_msgs/Header": __import__("std_msgs.msg").msg.Header}
TOPICS = ["/ptrz/pan_position_controller/state", "/ptrz/pan_position_controller", "/joint_states"]


def test_expand_and_split():
    assert expand("/pose/position/x:y") == ["/pose/position/x", "/pose/position/y"]
    assert expand("/a/b") == ["/a/b"]
    assert split_topic("/ptrz/pan_position_controller/state/process_value", TOPICS) == \
        ("/ptrz/pan_position_controller/state", "process_value")      # the longest topic wins
    assert split_topic("joint_states/position[1]", TOPICS) == ("/joint_states", "position[1]")
    assert split_topic("/nothing/x", TOPICS) is None


def test_parse_fields():
    assert parse_fields("pose/position/x") == [("pose", None), ("position", None), ("x", None)]
    assert parse_fields("position[2]") == [("position", 2)]
    with pytest.raises(PlotError, match="'position\\[x\\]' is not a field name"):
        parse_fields("position[x]")


@pytest.mark.parametrize("cls,path,message", [
    (JointControllerState, "proces_value",
     "'proces_value' is not a field of control_msgs/JointControllerState \\(its fields: header, set_point"),
    (JointState, "position",
     "/t/position is an array \\(float64\\[\\]\\): give an index, e.g. position\\[0\\]"),
    (JointState, "name[0]", "/t/name is a string"),
    (JointControllerState, "p[1]", "/t/p is not an array \\(float64\\): drop the \\[1\\]"),
    (PoseStamped, "pose/position", "/t/pose/position is a geometry_msgs/Point message, not a number; "
                                   "plot one of its fields, e.g. /t/pose/position/x"),
    (JointControllerState, "p/x", "/t/p is a float64 and has no field 'x'"),
    (JointControllerState, "", "give a numeric field to plot, e.g. /t/set_point"),
])
def test_bad_fields_name_what_exists(cls, path, message):
    with pytest.raises(PlotError, match=message):
        check_path(cls, parse_fields(path), CLASSES.get, "/t")


def test_extract_numbers_bools_times_and_short_arrays():
    js = JointState(position=[0.5, 1.5])
    assert check_path(JointState, parse_fields("position[1]"), CLASSES.get) == "float64"
    assert extract(js, parse_fields("position[1]")) == 1.5
    assert extract(js, parse_fields("position[5]")) is None
    s = JointControllerState(antiwindup=True, process_value=float("nan"))
    assert extract(s, parse_fields("antiwindup")) == 1.0
    assert extract(s, parse_fields("process_value")) is None
    ps = PoseStamped()
    ps.header.stamp.secs, ps.header.stamp.nsecs = 3, 500000000
    assert check_path(PoseStamped, parse_fields("header/stamp"), CLASSES.get) == "time"
    assert extract(ps, parse_fields("header/stamp")) == 3.5


def test_store_window_csv_round_trip_and_png(tmp_path):
    store = SeriesStore(["/a/x", "/a/y"])
    for i in range(200):
        t = 100.0 + i * 0.05
        store.append("/a/x", t, math.sin(t))
        store.append("/a/y", t, 0.1 * i)
    assert store.span() == pytest.approx(9.95)
    xs, ys = store.window(2.0)["/a/x"]
    assert xs[0] == pytest.approx(7.95) and xs[-1] == pytest.approx(9.95) and len(xs) == 41
    assert len(store.window(0)["/a/y"][0]) == 200
    back = read_csv(write_csv(store, str(tmp_path / "s.csv")))
    assert len(back["/a/x"]) == 200
    assert all(abs(a[0] - b[0]) < 1e-9 and a[1] == b[1] for a, b in zip(back["/a/x"], store.data["/a/x"]))
    png = write_png(store, str(tmp_path / "s.png"), 5.0, "title")
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(PlotError, match="is not an rqt_plot CSV"):
        (tmp_path / "bad.csv").write_text("a,b\n1,2\n")
        read_csv(str(tmp_path / "bad.csv"))


def test_store_keeps_at_most_max_samples():
    store = SeriesStore(["/s"], max_samples=10)
    for i in range(25):
        store.append("/s", float(i), float(i))
    assert [t for t, _ in store.data["/s"]] == [float(i) for i in range(15, 25)]


def test_trim_keeps_exactly_the_duration():
    store = SeriesStore(["/s"])
    for i in range(100):
        store.append("/s", 10.0 + 0.1 * i, 0.0)
    store.trim(5.0)
    assert store.span() == pytest.approx(5.0) and len(store.data["/s"]) == 51


def test_trim_never_exceeds_the_duration_by_rounding():
    """A sample at t0 + duration whose difference to t0 rounds above the duration (3.05 + 5.0 =
    8.05, 8.05 - 3.05 = 5.000000000000001) is dropped rather than making the span longer than
    asked."""
    t0 = 3.05
    store = SeriesStore(["/s"])
    for t in (t0, 6.0, t0 + 5.0, 9.0):
        store.append("/s", t, 0.0)
    store.trim(5.0)
    kept = [t for t, _ in store.data["/s"]]
    assert kept[-1] - kept[0] <= 5.0 and kept == [t0, 6.0]

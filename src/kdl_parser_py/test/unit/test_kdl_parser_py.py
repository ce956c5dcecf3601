"""Tier 1: kdl_parser_py.urdf has ROS's API and builds the trees kdl_parser builds."""
import os
import socket
import subprocess
import time

import PyKDL
import pytest

from kdl_parser_py.urdf import treeFromFile, treeFromParam, treeFromString, treeFromUrdfModel
from urdf_parser_py.urdf import URDF

ARM = """<robot name="arm">
  <link name="base"/>
  <link name="upper"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="lower"><inertial><mass value="0.5"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="tool"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
  <joint name="slide" type="prismatic"><parent link="upper"/><child link="lower"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 0 1"/><limit lower="0" upper="0.3" effort="10" velocity="1"/></joint>
  <joint name="flange" type="fixed"><parent link="lower"/><child link="tool"/><origin xyz="0.1 0 0"/></joint>
</robot>"""


def tip_position(tree, q):
    chain = tree.getChain("base", "tool")
    qa = PyKDL.JntArray(chain.getNrOfJoints())
    for i, v in enumerate(q):
        qa[i] = v
    frame = PyKDL.Frame()
    PyKDL.ChainFkSolverPos_recursive(chain).JntToCart(qa, frame)
    return [frame.p[i] for i in range(3)]


def test_tree_from_string_counts_and_fk():
    ok, tree = treeFromString(ARM)
    assert ok
    assert isinstance(tree, PyKDL.Tree)
    assert tree.getNrOfSegments() == 3   # every link but the root, fixed ones included
    assert tree.getNrOfJoints() == 2     # revolute + prismatic
    # shoulder at +90 deg about y tips the upper arm (0.4 + 0.2 slide) and the 0.1 flange over
    x, y, z = tip_position(tree, [1.5707963267948966, 0.2])
    assert x == pytest.approx(0.6, abs=1e-9)
    assert y == pytest.approx(0.0, abs=1e-9)
    assert z == pytest.approx(0.5 - 0.1, abs=1e-9)


def test_model_file_and_string_agree(tmp_path):
    path = tmp_path / "arm.urdf"
    path.write_text(ARM)
    trees = [treeFromString(ARM), treeFromFile(str(path)), treeFromUrdfModel(URDF.from_xml_string(ARM))]
    assert all(ok for ok, _ in trees)
    tips = [tip_position(tree, [0.3, 0.1]) for _, tree in trees]
    assert tips[0] == pytest.approx(tips[1]) and tips[0] == pytest.approx(tips[2])


@pytest.mark.parametrize("xml", ["", "<robot name='x'>",
                                 "<robot name='x'><link name='a'/><link name='b'/></robot>"])
def test_bad_description_is_not_ok(xml, caplog):
    ok, tree = treeFromString(xml)
    assert not ok and tree is None
    assert "cannot build a KDL tree" in caplog.text


def test_missing_file_names_it(caplog):
    ok, tree = treeFromFile("/nonexistent/robot.urdf")
    assert (ok, tree) == (False, None)
    assert "/nonexistent/robot.urdf" in caplog.text


def test_quiet_logs_nothing(caplog):
    assert treeFromString("<robot", quiet=True) == (False, None)
    assert caplog.text == ""


@pytest.fixture()
def master():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    uri = "http://127.0.0.1:%d" % port
    proc = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    old = os.environ.get("ROS_MASTER_URI")
    os.environ["ROS_MASTER_URI"] = uri
    import rosgraph
    deadline = time.monotonic() + 20
    while not rosgraph.is_master_online(uri):
        assert time.monotonic() < deadline, "rosmaster did not come up"
        time.sleep(0.05)
    yield uri
    proc.terminate()
    proc.wait(10)
    if old is None:
        del os.environ["ROS_MASTER_URI"]
    else:
        os.environ["ROS_MASTER_URI"] = old


def test_tree_from_param(master, caplog):
    import rosgraph
    rosgraph.Master("/test").setParam("/robot_description", ARM)
    ok, tree = treeFromParam("robot_description")
    assert ok and tree.getNrOfJoints() == 2
    assert treeFromParam("no_such_description") == (False, None)
    assert "no_such_description" in caplog.text and "is not set" in caplog.text

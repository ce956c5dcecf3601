"""Tier 1: the world and launch files gazebo_ros users name, as modrob_sim has them.

Every world file of modrob_sim/worlds loads, settles for 2 s without a blow-up and has the models
its launch file promises; each of gazebo_ros's launch files (empty_world, range_world, shapes_world,
mud_world, rubble_world, willowgarage_world, elevator_world) exists with gazebo_ros's arguments;
the GUI's display check tells a usable display from none.
"""
import glob
import math
import os
import socket
import xml.etree.ElementTree as ET

import pytest

from modrob_sim.gazebo_ros import display
from modrob_sim.gazebo_ros.resources import PACKAGE_DIR, ResourceResolver
from modrob_sim.gazebo_ros.world_file import find_world, world_physics
from modrob_sim.physics import World

#: world -> (models it must have, a check of the state after 2 s)
WORLDS = {
    "empty.world": (["ground_plane"], None),
    "empty_world.world": (["ground_plane"], None),
    "shapes.world": (["ground_plane", "box", "sphere", "cylinder"],
                     lambda w: all(abs(w.models[n].pose[0][2] - 0.5) < 0.01
                                   for n in ("box", "sphere", "cylinder"))),
    "rubble.world": (["ground_plane"] + ["rubble_%02d" % i for i in range(1, 19)],
                     lambda w: max(m.pose[0][2] for n, m in w.models.items()
                                   if n.startswith("rubble")) < 1.0),
    "willowgarage.world": (["ground_plane", "willowgarage"],
                           lambda w: len(w.models["willowgarage"].links) == 24),
    "mud.world": (["ground_plane", "pendulum_thick_mud", "pendulum_thin_mud", "pendulum_no_mud",
                   "mud_pit_thin", "mud_pit_thick"],
                  # the arms fell from horizontal and swing about the hinge at the post's top
                  lambda w: abs(w.models["pendulum_no_mud"].joints["upper_joint"].velocity) > 0.1
                  and abs(math.dist(w.models["pendulum_no_mud"].links["upper_link"].pose[0], (2.0, 0.0, 2.1))
                          - 0.25) < 0.002),
    "elevator_ros.world": (["ground_plane", "building", "elevator"],
                           lambda w: abs(w.models["elevator"].joints["lift"].position) < 0.01),
    "gazebo_ros_range.world": (["ground_plane", "wall", "sonar_post", "target_box"], None),
}

#: gazebo_ros (Noetic) launch file -> the arguments it declares
GAZEBO_ROS_LAUNCH_ARGS = {
    "empty_world": ["paused", "use_sim_time", "extra_gazebo_args", "gui", "recording", "headless", "debug",
                    "physics", "verbose", "output", "world_name", "respawn_gazebo", "use_clock_frequency",
                    "pub_clock_frequency", "enable_ros_network", "server_required", "gui_required"],
    "range_world": ["paused", "use_sim_time", "extra_gazebo_args", "gui", "debug", "physics", "verbose",
                    "output", "world"],
    "elevator_world": ["paused", "use_sim_time", "extra_gazebo_args", "gui", "recording", "headless", "debug",
                       "physics", "verbose", "output", "world_name"],
    "shapes_world": [], "mud_world": [], "rubble_world": [], "willowgarage_world": [],
}


def test_every_world_file_is_tested():
    shipped = sorted(os.path.basename(p) for p in glob.glob(os.path.join(PACKAGE_DIR, "worlds", "*.world")))
    assert shipped == sorted(WORLDS)


@pytest.mark.parametrize("name", sorted(WORLDS))
def test_world_loads_settles_and_has_its_models(name):
    resolver = ResourceResolver()
    path = find_world("worlds/" + name, resolver)
    text = open(path).read()
    assert world_physics(text).get("time_step", 0.001) == 0.001
    world = World(resource_resolver=resolver)
    models = world.add_sdf(text)
    expected, check = WORLDS[name]
    assert sorted(m.name for m in models) == sorted(expected)
    world.step(2000)
    assert world.pop_events() == []
    if check is not None:
        assert check(world)
    world.close()


@pytest.mark.parametrize("launch", sorted(GAZEBO_ROS_LAUNCH_ARGS))
def test_gazebo_ros_launch_files_take_gazebo_ros_arguments(launch):
    root = ET.parse(os.path.join(PACKAGE_DIR, "launch", launch + ".launch")).getroot()
    declared = {a.get("name") for a in root.findall("arg") if a.get("value") is None}
    missing = set(GAZEBO_ROS_LAUNCH_ARGS[launch]) - declared
    assert not missing, "%s.launch lacks gazebo_ros's arguments %s" % (launch, sorted(missing))
    includes = [i.get("file") for i in root.iter("include")]
    if launch != "empty_world":
        assert includes == ["$(find modrob_sim)/launch/empty_world.launch"]


def test_connect_display_tells_a_display_from_none(tmp_path, monkeypatch):
    def problem(env):
        conn, why = display.connect_display(env)
        assert (conn is None) != (why is None)
        if conn is not None:
            conn.close()
        return why
    assert problem({}) == "DISPLAY is not set"
    assert "not of the form" in problem({"DISPLAY": "nonsense"})
    monkeypatch.setattr(display, "X_SOCKET_DIR", str(tmp_path))
    assert "accepts no connection" in problem({"DISPLAY": ":57"})
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(str(tmp_path / "X57"))
    server.listen(8)
    try:
        assert problem({"DISPLAY": ":57"}) is None
        assert problem({"DISPLAY": ":57.0"}) is None
        # the connection is returned open (gzclient holds it while RViz runs)
        conn, _ = display.connect_display({"DISPLAY": ":57"})
        assert conn.getpeername() == str(tmp_path / "X57")
        conn.close()
    finally:
        server.close()

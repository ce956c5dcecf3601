"""spawn_model's command line is gazebo_ros's: the same flags, required groups and -J pairs."""
import pytest

from modrob_sim.gazebo_ros.spawn_model import SpawnModelCommand, build_parser


def test_gazebo_ros_command_line_parses():
    cmd = SpawnModelCommand(["-urdf", "-param", "robot_description", "-model", "arm", "-x", "1", "-Y", "0.5",
                             "-J", "joint1", "0.3", "-J", "joint2", "-1.2", "-unpause",
                             "-robot_namespace", "/arm", "-reference_frame", "table::top"])
    a = cmd.args
    assert a.urdf and a.param == "robot_description" and a.model == "arm"
    assert (a.x, a.y, a.z, a.R, a.P, a.Y) == (1.0, 0.0, 0.0, 0.0, 0.0, 0.5)
    assert a.joints == [("joint1", 0.3), ("joint2", -1.2)]
    assert a.unpause and a.robot_namespace == "/arm" and a.reference_frame == "table::top"
    assert cmd.ns == "/gazebo"


@pytest.mark.parametrize("argv", [
    ["-param", "robot_description", "-model", "m"],            # neither -urdf nor -sdf
    ["-urdf", "-sdf", "-param", "p", "-model", "m"],            # both
    ["-urdf", "-model", "m"],                                   # no source
    ["-urdf", "-file", "f", "-param", "p", "-model", "m"],      # two sources
    ["-urdf", "-file", "f"],                                    # no -model
])
def test_invalid_command_lines_exit_2(argv):
    with pytest.raises(SystemExit) as e:
        build_parser().parse_args(argv)
    assert e.value.code == 2


def test_non_numeric_joint_position_is_refused():
    with pytest.raises(SystemExit) as e:
        SpawnModelCommand(["-urdf", "-file", "f", "-model", "m", "-J", "j1", "abc"])
    assert "j1" in str(e.value)


def test_gzserver_arguments_of_gazebo_ros_launch_files():
    from modrob_sim.gazebo_ros.node_params import _as_list, parse_server_args
    a = parse_server_args(["-u", "--verbose", "-e", "ode", "worlds/empty.world", "--lockstep"])
    assert a["paused"] and a["verbose"] and a["physics"] == "ode" and a["world"] == "worlds/empty.world"
    assert a["ignored"] == ["--lockstep"]
    assert not parse_server_args(["", ""])["paused"]
    assert _as_list("a.b, c.d") == ["a.b", "c.d"] and _as_list(["x"]) == ["x"] and _as_list(None) == []

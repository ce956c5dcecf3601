"""make demo SCENARIO=ptrz ends at once when the simulator dies: the demo's launch makes it required."""
import roslaunch.config
import rospkg

from ptrz_camera import demo


def launch_nodes(*args):
    path = rospkg.RosPack().get_path("ptrz_camera") + "/launch/tracking.launch"
    config = roslaunch.config.load_config_default([(path, list(args))], None, verbose=False)
    return {n.name: n for n in config.nodes}


def test_the_demos_launch_makes_the_simulator_required():
    assert launch_nodes("gui:=false", "cameras:=1")["gazebo"].required is False   # as gazebo_ros
    assert launch_nodes("gui:=false", "cameras:=1", "server_required:=true")["gazebo"].required is True


def test_a_stopped_run_names_the_simulators_fatal_message(tmp_path, capsys):
    (tmp_path / "ptrz_launch.log").write_text(
        "[INFO] starting\n[FATAL] [1.0, 0.0]: gazebo: cannot start: libfoo.so is out of date\n"
        "[ERROR] later\n")
    args = type("Args", (), {"scenario": "ptrz", "out": str(tmp_path)})()
    assert demo.stopped(args) == 1
    out = capsys.readouterr().out
    assert "cannot start: libfoo.so is out of date" in out
    assert "RESULT ptrz: FAILURE -- the simulation stopped" in out

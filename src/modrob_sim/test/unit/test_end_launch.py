"""modrob_sim.end_launch: a scenario node ends its roslaunch as Ctrl-C does, and only a roslaunch."""
import os
import signal

from modrob_sim import end_launch


def fake_proc(tmp_path, pid, *argv):
    d = tmp_path / str(pid)
    d.mkdir()
    (d / "cmdline").write_bytes(b"\0".join(a.encode() for a in argv) + b"\0")
    return str(tmp_path)


def test_roslaunch_is_recognised_directly_or_through_its_interpreter(tmp_path):
    proc = fake_proc(tmp_path, 10, "/usr/bin/python3", "/usr/bin/roslaunch", "modrob_motion", "x.launch")
    assert end_launch.parent_is_roslaunch(10, proc)
    proc = fake_proc(tmp_path, 11, "roslaunch", "-p", "11311", "pkg", "x.launch")
    assert end_launch.parent_is_roslaunch(11, proc)


def test_rostest_rosrun_and_scripts_are_not_ended(tmp_path):
    proc = fake_proc(tmp_path, 12, "/usr/bin/python3", "/usr/bin/rostest", "pkg", "x.test")
    assert not end_launch.parent_is_roslaunch(12, proc)
    proc = fake_proc(tmp_path, 13, "/usr/bin/python3", "scripts/demo.py", "roslaunch")
    assert not end_launch.parent_is_roslaunch(13, proc)
    assert not end_launch.parent_is_roslaunch(99999, proc)   # gone


def test_end_launch_sends_sigint_to_the_parent_and_waits_for_shutdown(monkeypatch):
    sent, looks = [], []
    monkeypatch.setattr(end_launch, "parent_is_roslaunch", lambda: True)

    def is_shutdown():
        looks.append(1)
        return len(looks) > 2
    assert end_launch.end_launch(is_shutdown, timeout=10, kill=lambda pid, sig: sent.append((pid, sig)))
    assert sent == [(os.getppid(), signal.SIGINT)] and len(looks) == 3


def test_finish_scenario_says_the_world_stays_up(monkeypatch):
    said = []
    monkeypatch.setattr(end_launch, "parent_is_roslaunch", lambda: True)
    end_launch.finish_scenario(said.append, False, lambda: False)
    assert "Ctrl-C ends the launch" in said[0]
    monkeypatch.setattr(end_launch, "parent_is_roslaunch", lambda: False)
    end_launch.finish_scenario(said.append, True, lambda: False)   # under rostest: nothing to end
    assert len(said) == 1

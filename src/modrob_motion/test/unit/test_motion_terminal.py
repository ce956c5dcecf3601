"""Tier 1: the terminal line parser and the terminal's behaviour (no ROS)."""
import math
import os

import pytest

from modrob_motion import terminal_parser as tp
from modrob_motion.errors import MotionError, ParseError
from modrob_motion.robot_info import robot_info_from_urdf
from modrob_motion.terminal import DictDirectory, MotionTerminal

with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "test_motion_arm_gripper.urdf")) as _f:
    ARM_URDF = _f.read()


@pytest.mark.parametrize("line,cmd", [
    ("0.1 0.5 -0.3", tp.JointTarget([0.1, 0.5, -0.3])),
    ("  0.1, 0.5,-0.3  ", tp.JointTarget([0.1, 0.5, -0.3])),
    ("deg 90 -180", tp.JointTarget([math.pi / 2, -math.pi])),
    ("#1", tp.SelectRobot(1)),
    ("# 12", tp.SelectRobot(12)),
    ("home", tp.Home()), ("HOME", tp.Home()), ("help", tp.Help()), ("?", tp.Help()),
    ("open", tp.GripperCommand("open")), ("close", tp.GripperCommand("close")),
    ("xyz 0.4 0.1 1.3", tp.CartesianTarget([0.4, 0.1, 1.3])),
    ("state", tp.State()), ("quit", tp.Quit()), (None, tp.Quit()),
    ("", None), ("   ", None),
])
def test_parse_ok(line, cmd):
    assert tp.parse_line(line) == cmd


@pytest.mark.parametrize("line,reason", [
    ("#x", "robot is chosen by its number"),
    ("#-1", "robot is chosen by its number"),
    ("0.1 foo 3", "'foo' is neither a number nor a command"),
    ("0.1 nan", "'nan' is not a finite number"),
    ("xyz 1 2", "xyz needs three numbers"),
    ("xyz 1 2 inf", "not a finite number"),
    ("home now", "'home' takes no arguments"),
    ("close 3", "'close' takes no arguments"),
    ("deg", "deg needs joint angles"),
    ("jump", "'jump' is neither a number nor a command"),
])
def test_parse_errors_are_one_line(line, reason):
    with pytest.raises(ParseError) as err:
        tp.parse_line(line)
    assert reason in str(err.value)
    assert "\n" not in str(err.value)


def make_terminal(ik=None):
    robots = {0: robot_info_from_urdf(0, ARM_URDF), 1: robot_info_from_urdf(1, ARM_URDF)}
    return MotionTerminal(DictDirectory(robots), robot_id=0, ik_solver=ik)


def test_joint_line_gives_command_for_current_robot():
    t = make_terminal()
    r = t.handle("0.2 -0.4")
    assert r.ok and r.command.robot_id == 0
    assert r.command.names == ["joint1", "joint2"] and r.command.positions == [0.2, -0.4]
    assert t.handle("#1").ok
    r = t.handle("home")
    assert r.command.robot_id == 1 and r.command.positions == [0.0, 0.0]
    assert t.prompt() == "modrob1> "


def test_gripper_open_close():
    t = make_terminal()
    r = t.handle("close")
    assert r.command.names == ["finger_left_joint", "finger_right_joint"]
    assert r.command.positions == [0.0, 0.0]
    assert t.handle("open").command.positions == [0.03, 0.03]


@pytest.mark.parametrize("line,reason", [
    ("1 2 3", "modrob0 has 2 arm joints (joint1, joint2); got 3 angles"),
    ("0 2.5", "above its upper limit"),
    ("#5", "no robot 5; robots here: #0, #1"),
    ("xyz 1 2 3", "needs the KDL IK solver"),
    ("bogus", "neither a number nor a command"),
])
def test_bad_lines_reply_and_keep_state(line, reason):
    t = make_terminal()
    r = t.handle(line)
    assert not r.ok and r.command is None and reason in r.text
    assert t.robot_id == 0 and t.handle("0 0").ok


def test_xyz_uses_ik_with_seed_and_reports_unreachable():
    seen = {}

    def ik(info, xyz, seed):
        seen["seed"] = list(seed)
        if xyz[2] > 5:
            raise MotionError("(%.1f, %.1f, %.1f) is out of reach of modrob%d" % (xyz + (info.robot_id,)))
        return [0.3, 0.1]
    t = make_terminal(ik)
    t.handle("0.5 0.6")
    r = t.handle("xyz 0.1 0.2 0.3")
    assert r.ok and r.command.positions == [0.3, 0.1] and seen["seed"] == [0.5, 0.6]
    r = t.handle("xyz 0 0 9")
    assert not r.ok and "out of reach" in r.text


def test_help_and_state_and_quit():
    t = make_terminal()
    assert "xyz <x> <y> <z>" in t.handle("help").text
    t.handle("0.1 0.2")
    assert "0.1000" in t.handle("state").text
    assert t.handle("quit").quit


def test_no_robot_yet():
    t = MotionTerminal(DictDirectory({}))
    r = t.handle("0 0")
    assert not r.ok and "no robot is running yet" in r.text


def test_one_command_table_drives_parsing_help_and_docs():
    """Every word of the command table parses to its command, appears in help, and the docs show
    the table as the terminal has it (regenerate: python3 -m modrob_motion.terminal_parser)."""
    samples = {None: "0.1 0.2", "#": "#1", "deg": "deg 10", "degrees": "degrees 10", "xyz": "xyz 0 0 1"}
    help_lines = tp.help_text()
    for spec in tp.COMMANDS:
        for word in spec.words:
            line = samples.get(word, word)
            expected = type(spec.parse(word if word not in (None, "#") else line.split()[0],
                                       line.split()[1:] if word else line.split()))
            assert type(tp.parse_line(line)) is expected, line
            if word not in (None, "#"):
                assert word in help_lines, "help does not mention '%s'" % word
    docs = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..", "docs",
                        "bulbs_and_slides.md")
    with open(docs) as f:
        assert tp.markdown_table() in f.read(), \
            "docs/bulbs_and_slides.md's terminal table differs: python3 -m modrob_motion.terminal_parser"

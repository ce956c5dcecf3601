"""Keyboard teleop core: one key table drives help and dispatch; steps, selection, limits."""
import math

import pytest

from katana_sim import kinematics as kin
from katana_sim.gripper import CLOSED_ANGLE, OPEN_ANGLE
from katana_sim.teleop import KEYS, TeleopState, help_text

Q = [0.0, 1.0, -1.0, 0.5, 0.0]


def test_every_key_of_the_table_is_in_the_help_and_does_something():
    text = help_text()
    state = TeleopState()
    for keys, action, words in KEYS:
        assert words in text
        for k in keys:
            cmd = state.handle(k, Q)
            assert "not bound" not in cmd.text, k


def test_w_and_s_step_the_selected_joint_and_stop_at_its_limit():
    state = TeleopState(increment=0.1)
    state.handle("2", Q)
    cmd = state.handle("w", Q)
    assert cmd.kind == "move" and cmd.positions == pytest.approx([0.0, 1.0, -0.9, 0.5, 0.0])
    cmd = state.handle("s", [0.0, 1.0, kin.LOWER[2] + 0.05, 0.5, 0.0])
    assert cmd.positions[2] == kin.LOWER[2] and "joint limit" in cmd.text


def test_selection_wraps_and_increment_never_goes_negative():
    state = TeleopState(increment=math.radians(1), step=math.radians(1))
    state.handle("a", Q)
    assert state.joint == 4
    state.handle("d", Q)
    assert state.joint == 0
    state.handle("-", Q)
    state.handle("#", Q)
    assert state.increment == 0.0
    state.handle("+", Q)
    assert state.increment == pytest.approx(math.radians(1))


def test_gripper_home_info_quit_and_unknown_keys():
    state = TeleopState()
    assert state.handle("o", Q).gripper == OPEN_ANGLE
    assert state.handle("c", Q).gripper == CLOSED_ANGLE
    assert state.handle("r", Q).positions == list(kin.HOME)
    info = state.handle("i", Q)
    assert info.kind == "info" and kin.JOINTS[3] in info.text
    assert state.handle("q", Q).kind == "quit"
    assert state.handle("\x03", Q).kind == "quit"
    assert "not bound" in state.handle("z", Q).text

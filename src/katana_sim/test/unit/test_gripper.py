"""The gripper controller (pure): set-point ramp, torque limit, reached / stalled / held, bad goals."""
import math

import pytest

from katana_sim.errors import ConfigError
from katana_sim.gripper import CLOSED_ANGLE, OPEN_ANGLE, GripperController

DT = 0.001


def run(ctrl, plant, seconds):
    """A two-finger plant: unit-less inertia, optional block (an object) the fingers cannot pass."""
    t = plant["t"]
    for _ in range(int(seconds / DT)):
        efforts = ctrl.update(t, DT, plant["q"], plant["v"])
        for i, e in enumerate(efforts):
            plant["v"][i] += e / plant["inertia"] * DT - plant["v"][i] * 0.02
            plant["q"][i] += plant["v"][i] * DT
            if plant["block"] is not None and plant["q"][i] < plant["block"]:
                plant["q"][i], plant["v"][i] = plant["block"], 0.0
            plant["q"][i] = min(max(plant["q"][i], CLOSED_ANGLE), OPEN_ANGLE)
        t += DT
        if not ctrl.active and ctrl._pending is None and ctrl.result is not None:
            break
    plant["t"] = t


def plant(q=0.0, block=None):
    return {"t": 0.0, "q": [q, q], "v": [0.0, 0.0], "inertia": 2e-4, "block": block}


def test_opens_at_start_then_closes_on_nothing():
    ctrl, p = GripperController(), plant(0.0)
    run(ctrl, p, 2.0)
    assert ctrl.result is None and p["q"] == pytest.approx([OPEN_ANGLE] * 2, abs=0.01)
    assert ctrl.command(CLOSED_ANGLE)[0]
    run(ctrl, p, 6.0)
    res = ctrl.result
    assert res.reached_goal and not res.stalled and not res.holding
    assert not ctrl.holding()


def test_closing_on_an_object_stalls_and_holds_with_the_torque_limit():
    ctrl, p = GripperController(max_torque=0.5), plant(OPEN_ANGLE, block=-0.14)
    ctrl.command(CLOSED_ANGLE, max_effort=0.3)
    run(ctrl, p, 6.0)
    res = ctrl.result
    assert res.stalled and not res.reached_goal and res.holding, res.text
    assert ctrl.holding()
    assert max(abs(e) for e in ctrl.efforts) == pytest.approx(0.3)   # the goal's limit, not more
    ctrl.command(CLOSED_ANGLE, max_effort=5.0)
    run(ctrl, p, 6.0)
    assert max(abs(e) for e in ctrl.efforts) == pytest.approx(0.5)   # never above max_torque


def test_setpoint_moves_at_the_finger_speed():
    ctrl, p = GripperController(speed=0.5), plant(OPEN_ANGLE)
    ctrl.update(0.0, DT, p["q"], p["v"])
    ctrl.command(CLOSED_ANGLE)
    for i in range(100):
        ctrl.update((i + 1) * DT, DT, p["q"], p["v"])
    assert ctrl.setpoint == pytest.approx(OPEN_ANGLE - 0.5 * 0.1, abs=1e-9)


@pytest.mark.parametrize("position, effort, words", [
    (float("nan"), 0.0, "position nan is not a finite number"),
    (0.1, float("inf"), "max_effort inf is not a finite number"),
    ("open", 0.0, "is not a finite number"),
])
def test_bad_goals_are_refused_with_the_reason(position, effort, words):
    ok, text = GripperController().command(position, effort)
    assert not ok and words in text


def test_out_of_range_goal_is_clamped_and_said():
    ctrl = GripperController()
    ok, text = ctrl.command(2.0)
    assert ok and "clamped" in text and ctrl._pending[0] == OPEN_ANGLE


def test_bad_configuration_names_the_parameter():
    with pytest.raises(ConfigError, match="max_torque"):
        GripperController(max_torque=-1)
    with pytest.raises(ConfigError, match="speed"):
        GripperController(speed=math.nan)

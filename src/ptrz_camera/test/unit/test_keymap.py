"""The keyboard teleop's key table and state machine (seed 002 section 3.2, appendix B.4)."""
import pytest

from ptrz_camera import keymap


def run(keys, **kw):
    state = keymap.TeleopState(**kw)
    outputs = [state.press(k) for k in keys]
    return state, outputs


def test_seed_key_map_moves_the_seeds_targets():
    state, _ = run("qwwaszxx")
    roll, pan, tilt = state.commands()
    assert roll == pytest.approx(0.1)      # q -0.1, w w +0.2
    assert pan == pytest.approx(0.0)       # a -0.1, s +0.1
    assert tilt == pytest.approx(0.1)      # z -0.1, x x +0.2


def test_step_is_multiplied_and_divided_by_1_1_from_0_1():
    state, _ = run("ee")
    assert state.diff == pytest.approx(0.1 * 1.1 * 1.1)
    state.press("s")
    assert state.commands()[1] == pytest.approx(0.121)
    state.press("d")
    assert state.diff == pytest.approx(0.11)


def test_home_returns_everything_and_resets_step_and_count():
    state, _ = run("eeqasx+")
    lines = state.press("h")
    assert state.commands() == (0.0, 0.0, 0.0)
    assert state.diff == keymap.DIFF
    assert state.status == 0
    assert state.fov == state.home_fov
    assert state.zoom_changed
    assert any("roll 0.0000" in line for line in lines)


def test_positions_and_step_are_printed_after_each_key_and_help_after_six():
    state = keymap.TeleopState()
    for i in range(1, 7):
        out = state.press("s")
        assert out[0] == keymap.STRIPES
        assert "pan %.4f" % (0.1 * i) in out[1]
        assert "step 0.1000" in out[2]
        has_help = any("Control Your ptrz camera" in line for line in out)
        assert has_help == (i == 6), "help after press %d" % i
    assert state.status == 0


def test_unbound_keys_do_nothing_and_ctrl_c_quits():
    state = keymap.TeleopState()
    assert state.press("") is None
    assert state.press("k") is None
    assert state.commands() == (0.0, 0.0, 0.0)
    assert state.press(keymap.CTRL_C) == []
    assert state.quit


def test_zoom_keys_change_fov_inside_the_range_and_refuse_outside():
    state = keymap.TeleopState(fov=1.0, fov_range=(0.7, 1.3))
    state.press("+")
    assert state.fov == pytest.approx(0.8) and state.zoom_changed
    out = state.press("+")       # 0.64 < 0.7
    assert state.fov == pytest.approx(0.8) and not state.zoom_changed
    assert any("outside the camera's range" in line for line in out)
    state.press("-")
    state.press("-")
    assert state.fov == pytest.approx(1.25)


def test_help_is_built_from_the_key_table():
    text = keymap.help_text("/ptrz2")
    for k in keymap.KEYS:
        assert k.key in text and k.help in text
    assert "/ptrz2" in text and "CTRL-C" in text
    assert len(keymap.BINDINGS) == len(keymap.KEYS)

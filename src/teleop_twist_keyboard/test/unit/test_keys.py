"""teleop_twist_keyboard's key map and speed keys, without ROS."""
import pytest

from keyboard_teleop.keys import CTRL_C, HELP, MOVE, KeyTeleop


def test_the_key_map_is_teleop_twist_keyboards():
    assert MOVE["i"] == (1, 0, 0, 0) and MOVE[","] == (-1, 0, 0, 0)
    assert MOVE["j"] == (0, 0, 0, 1) and MOVE["l"] == (0, 0, 0, -1)
    assert MOVE["u"] == (1, 0, 0, 1) and MOVE["o"] == (1, 0, 0, -1)
    assert MOVE["J"] == (0, 1, 0, 0) and MOVE["t"] == (0, 0, 1, 0)
    for key in "uiojlm,.UIOJLM<>tb":
        assert key in MOVE and key in HELP


def test_moving_keys_times_speed_and_turn():
    k = KeyTeleop(speed=0.5, turn=1.0)
    assert k.press("i")[0] == (0.5, 0.0, 0.0, 0.0)
    assert k.press("u")[0] == (0.5, 0.0, 0.0, 1.0)
    assert k.press("L")[0] == (0.0, -0.5, 0.0, 0.0)


def test_speed_keys_scale_and_are_capped():
    k = KeyTeleop(speed=0.5, turn=1.0, speed_limit=0.6)
    k.press("i")
    twist, lines, _q = k.press("q")
    assert twist == pytest.approx((0.55, 0, 0, 0)) and "speed 0.55" in lines[-1]
    twist, lines, _q = k.press("w")
    assert k.speed == 0.6 and "Linear speed limit reached!" in lines
    k.press("c")
    assert k.turn == pytest.approx(1.1 * 0.9)


def test_any_other_key_stops_and_a_timeout_while_standing_sends_nothing():
    k = KeyTeleop()
    k.press("i")
    assert k.press("k")[0] == (0.0, 0.0, 0.0, 0.0)
    assert k.press("")[0] is None
    k.press("i")
    assert k.press("")[0] == (0.0, 0.0, 0.0, 0.0)        # key released: the timeout stops the robot


def test_ctrl_c_stops_and_quits():
    k = KeyTeleop()
    k.press("i")
    twist, _lines, quit_ = k.press(CTRL_C)
    assert twist == (0.0, 0.0, 0.0, 0.0) and quit_


def test_help_again_after_fifteen_speed_changes():
    k = KeyTeleop()
    shown = [HELP in k.press("e" if n % 2 else "c")[1] for n in range(30)]
    assert [n for n, s in enumerate(shown) if s] == [14, 29]

"""control_toolbox::Pid semantics."""
import math

import pytest

from modrob_sim.errors import ControllerError, ModrobError
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.pid import Pid, PidGains


def test_p_only_and_derivative_by_finite_difference():
    pid = Pid(PidGains(p=2.0, d=0.5))
    assert pid.compute(1.0, 0.1) == pytest.approx(2.0 + 0.5 * (1.0 - 0.0) / 0.1)
    assert pid.compute(0.5, 0.1) == pytest.approx(1.0 + 0.5 * (0.5 - 1.0) / 0.1)


def test_given_error_dot_is_used():
    pid = Pid(PidGains(p=1.0, d=2.0))
    assert pid.compute(1.0, 0.01, error_dot=-3.0) == pytest.approx(1.0 - 6.0)


def test_integral_term_is_zero_without_i_clamp_as_in_ros_control():
    pid = Pid(PidGains(p=0.0, i=10.0))
    for _ in range(100):
        out = pid.compute(1.0, 0.01)
    assert out == 0.0 and pid.i_error == pytest.approx(1.0)


def test_integral_term_clamped_without_antiwindup():
    pid = Pid(PidGains(p=0.0, i=10.0, i_max=3.0, i_min=-3.0))
    outs = [pid.compute(1.0, 0.01) for _ in range(100)]
    assert outs[0] == pytest.approx(0.1)
    assert outs[-1] == pytest.approx(3.0)
    assert pid.i_error == pytest.approx(1.0)     # the state keeps growing without antiwindup


def test_antiwindup_clamps_the_integral_state():
    pid = Pid(PidGains(p=0.0, i=10.0, i_max=3.0, i_min=-3.0, antiwindup=True))
    for _ in range(100):
        pid.compute(1.0, 0.01)
    assert pid.i_error == pytest.approx(0.3)
    # unwinding starts at once
    assert pid.compute(-1.0, 0.01) == pytest.approx(10.0 * 0.29)


def test_zero_dt_and_nan_give_zero():
    pid = Pid(PidGains(p=1.0))
    assert pid.compute(1.0, 0.0) == 0.0
    assert pid.compute(float("nan"), 0.01) == 0.0


def test_gains_from_params_as_control_toolbox_reads_them():
    g = PidGains.from_params(Params({"p": 100, "i": 0.01, "d": 10, "i_clamp": -2.0}, "/ptrz/c/pid"))
    assert (g.p, g.i, g.d, g.i_max, g.i_min, g.antiwindup) == (100.0, 0.01, 10.0, 2.0, -2.0, False)
    g = PidGains.from_params(Params({"p": 1, "i_clamp": 2, "i_clamp_min": 5, "i_clamp_max": -7,
                                     "antiwindup": True}, "/x"))
    assert (g.i_min, g.i_max, g.antiwindup) == (-5.0, 7.0, True)


def test_missing_p_names_the_full_parameter_path():
    with pytest.raises(ControllerError) as err:
        PidGains.from_params(Params({"i": 1.0}, "/ptrz/roll_position_controller/pid"))
    assert "/ptrz/roll_position_controller/pid/p" in str(err.value)
    assert isinstance(err.value, ModrobError)


def test_non_numeric_gain_is_refused_with_its_path():
    with pytest.raises(ControllerError, match="/a/pid/d must be a number"):
        PidGains.from_params(Params({"p": 1.0, "d": "ten"}, "/a/pid"))
    with pytest.raises(ControllerError, match="finite"):
        PidGains.from_params(Params({"p": math.inf}, "/a/pid"))

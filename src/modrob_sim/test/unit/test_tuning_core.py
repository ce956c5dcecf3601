"""Tier 1: relay feedback, ZN tables, sine response and step metrics on a one-joint integrator."""
import math

import numpy as np
import pytest

from modrob_sim.tuning import TuningError
from modrob_sim.tuning.autotune import auto_tune
from modrob_sim.tuning.experiments import run_pid, step_setpoint
from modrob_sim.tuning.loops import IntegratorLoop
from modrob_sim.tuning.metrics import Trace, sine_fit, step_metrics
from modrob_sim.tuning.relay import holding_effort, relay_test
from modrob_sim.tuning.report import controller_yaml
from modrob_sim.tuning.rules import gains_from_ultimate
from modrob_sim.tuning.sine import sine_response

import yaml


def test_zn_classic_table():
    g = gains_from_ultimate(100.0, 0.4, "classic")
    assert g["p"] == pytest.approx(60.0)
    assert g["i"] == pytest.approx(60.0 / 0.2)
    assert g["d"] == pytest.approx(60.0 * 0.05)
    with pytest.raises(TuningError, match="unknown tuning rule 'magic'"):
        gains_from_ultimate(1, 1, "magic")
    with pytest.raises(TuningError, match="must be positive"):
        gains_from_ultimate(-1, 1)


def test_step_metrics_of_first_order_response():
    t = np.linspace(0, 5, 5001)
    q = np.where(t >= 1.0, 1 - np.exp(-(t - 1.0) / 0.5), 0.0)
    m = step_metrics(Trace(t, np.ones_like(t), q, 0 * t), 1.0, 0.0, 1.0)
    assert m.rise_time == pytest.approx(0.5 * math.log(9), rel=0.01)   # 10-90 % of a first-order lag
    assert m.overshoot == 0.0
    assert m.settling_time == pytest.approx(0.5 * math.log(50), rel=0.01)


def test_sine_fit_recovers_amplitude_and_phase():
    t = np.linspace(0, 4, 4000)
    amp, ph, off = sine_fit(t, 0.3 * np.sin(2 * math.pi * 0.5 * t - 0.4) + 0.1, 0.5)
    assert amp == pytest.approx(0.3, rel=1e-6) and ph == pytest.approx(-0.4, abs=1e-6)
    assert off == pytest.approx(0.1)


def test_relay_gives_the_describing_function_ultimate_point():
    # Plant 1/(s (I s + b)) with a pure 1-step delay from the explicit loop: relay with hysteresis
    # must oscillate; Ku from the describing function must make the loop's gain |G(j wu)| Ku ~ 1.
    loop = IntegratorLoop(inertia=0.05, damping=0.5, effort_limit=50.0)
    rr = relay_test(loop, 0.0, relay=2.0, hysteresis=0.002)
    wu = 2 * math.pi / rr.tu
    g = 1.0 / (wu * math.hypot(0.05 * wu, 0.5))
    assert rr.ku * g == pytest.approx(1.0, rel=0.15)
    assert rr.amplitude > 0.002


def test_relay_refuses_when_it_cannot_oscillate():
    loop = IntegratorLoop(inertia=0.05, damping=0.5, effort_limit=1.0)
    with pytest.raises(TuningError, match="exceed the joint's effort limit"):
        relay_test(loop, 0.0, relay=0.8, hysteresis=0.001, bias=0.5)


def test_holding_effort_measures_gravity():
    loop = IntegratorLoop(inertia=0.05, damping=0.2, gravity_torque=3.0, effort_limit=20.0)
    bias, q = holding_effort(loop, 0.5, {"p": 200.0, "i": 100.0, "d": 5.0, "i_clamp": 10.0})
    assert bias == pytest.approx(3.0 * math.sin(0.5), rel=0.05)


def test_auto_tune_improves_a_sluggish_loop_with_gravity():
    loop = IntegratorLoop(inertia=0.05, damping=0.2, gravity_torque=2.0, effort_limit=20.0)
    sluggish = {"p": 5.0, "i": 0.0, "d": 0.5, "i_clamp": 0.0}
    res = auto_tune(loop, 0.3, sluggish, rule="no_overshoot", refine=False)
    assert res.after.iae < 0.5 * res.before.iae
    assert res.after.overshoot < 0.25
    assert abs(res.after.steady_state_error) < 0.005
    assert res.sine_after.rms_error < res.sine_before.rms_error


def test_sine_response_of_a_stiff_loop_tracks():
    loop = IntegratorLoop(inertia=0.05, damping=0.2, effort_limit=50.0)
    s = sine_response(loop, {"p": 400.0, "i": 0.0, "d": 8.0}, 0.0, 0.2, 0.5)
    assert s.amplitude_ratio == pytest.approx(1.0, abs=0.05)
    assert s.rms_error < 0.02 and s.saturation == 0.0


def test_same_inputs_same_trace():
    loop = IntegratorLoop(inertia=0.05, damping=0.2, effort_limit=50.0)
    a = run_pid(loop, {"p": 100.0, "d": 3.0}, step_setpoint(0, 0.1, 0.1), 0.5, 0.0)
    b = run_pid(loop, {"p": 100.0, "d": 3.0}, step_setpoint(0, 0.1, 0.1), 0.5, 0.0)
    assert np.array_equal(a.position, b.position)


def test_yaml_outputs():
    text = controller_yaml("/modrob0", "joint2", {"p": 123.456789, "i": 1.0, "d": 2.0, "i_clamp": 3.0})
    data = yaml.safe_load(text)
    c = data["modrob0"]["joint2_position_controller"]
    assert c["type"] == "effort_controllers/JointPositionController" and c["pid"]["p"] == 123.46

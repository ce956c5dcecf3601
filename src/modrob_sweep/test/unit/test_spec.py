"""The sweep file -> trials (pure)."""
import os

import pytest

from modrob_sweep import SweepError
from modrob_sweep.spec import Sweep, load

FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures")
SWEEPS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "sweeps")


def test_grid_repetitions_and_seeds():
    s = load(os.path.join(FIX, "sweep_ok.yaml"), root="/ws")
    assert len(s.trials) == 2 * 3 * 2
    assert [t.index for t in s.trials] == list(range(12))
    # repetitions are the outer loop: the first six trials cover the whole grid once
    assert [(t.params["mu"], t.params["h"]) for t in s.trials[:6]] == [
        (0.2, 0.0), (0.2, 0.5), (0.2, 1.0), (0.4, 0.0), (0.4, 0.5), (0.4, 1.0)]
    assert [t.seed for t in s.trials] == [7 + k for k in range(12)]
    assert all(t.params["v0"] == 1.5 for t in s.trials)
    assert s.parameter_names == ["v0", "mu", "h", "c", "jitter", "k"]
    assert s.varying() == ["mu", "h", "c", "jitter", "k"]


def test_random_draws_are_seeded_per_trial():
    a = load(os.path.join(FIX, "sweep_ok.yaml"))
    b = load(os.path.join(FIX, "sweep_ok.yaml"), runs=5)     # more trials: the first ones draw the same
    for ta, tb in zip(a.trials, b.trials):
        assert ta.params == tb.params
    values = [t.params["jitter"] for t in a.trials]
    assert len(set(values)) == len(values)
    assert all(-0.004 <= v <= 0.004 for v in values)
    assert all(t.params["k"] in range(10) and t.params["c"] in ("a", "b") for t in a.trials)


def test_argv_and_result_path():
    s = load(os.path.join(FIX, "sweep_ok.yaml"), root="/ws")
    t = s.trials[4]
    argv = s.argv(t, "/o/0004", 12345)
    assert argv[:3] == ["python3", "-c", "print(1)"]
    assert argv[3:] == ["--mu", "0.4", "--h", "0.5", "--j", repr(t.params["jitter"]), "--seed", "11",
                        "--out", "/o/0004", "--port", "12345"]
    assert s.result_path(t, "/o/0004") == "/o/0004/r_4.yaml"


def test_demo_and_launch_commands():
    s = Sweep({"scenario": {"demo": "katana", "args": ["--seed", "{seed}"]}}, source="x.yaml", root="/ws")
    assert s.command == ["/ws/scripts/demo.sh", "katana", "--out", "{out}", "--seed", "{seed}"]
    assert s.name == "x" and len(s.trials) == 1
    s = Sweep({"scenario": {"launch": "modrob_sweep slide_trial.launch", "args": ["mu:=0.1"]}},
              source="y.yaml")
    assert s.command == ["roslaunch", "-p", "{port}", "modrob_sweep", "slide_trial.launch", "mu:=0.1"]


def test_select_keeps_parameters_and_seeds():
    s = load(os.path.join(FIX, "sweep_ok.yaml"))
    before = {t.index: (t.params, t.seed) for t in s.trials}
    s.select("5,2")
    assert [t.index for t in s.trials] == [2, 5]
    assert all(before[t.index] == (t.params, t.seed) for t in s.trials)
    with pytest.raises(SweepError, match="no trial 99"):
        s.select("99")


@pytest.mark.parametrize("fixture, message", [
    ("sweep_bad_placeholder.yaml", r"'\{friction\}' in 'mu:=\{friction\}' is neither a parameter"),
    ("sweep_bad_grid_and_points.yaml", "give parameters.grid or parameters.points, not both"),
])
def test_bad_files_are_refused_with_the_reason(fixture, message):
    with pytest.raises(SweepError, match=message):
        load(os.path.join(FIX, fixture))


@pytest.mark.parametrize("data, message", [
    ({"scenario": {"demo": "katana", "launch": "a b.launch"}}, "exactly one of demo"),
    ({"scenario": {"demo": "katana"}, "repetitions": 0}, "repetitions must be an integer >= 1"),
    ({"scenario": {"demo": "katana"}, "timeout_s": -1}, "timeout_s must be a positive number"),
    ({"scenario": {"demo": "katana"}, "parameters": {"random": {"x": {"beta": [1, 2]}}}},
     "parameters.random.x"),
    ({"scenario": {"demo": "katana"}, "parameters": {"mu": [1]}}, "put a parameter under one of them"),
    ({"scenario": {"demo": "katana"}, "parameters": {"fixed": {"out": 1}}},
     "'out' is a built-in placeholder"),
    ({"scenario": {"launch": ["pkg", "file.xml"]}}, r"scenario.launch is \[package, file.launch\]"),
    ({"scenario": {"demo": "katana"}, "reps": 3}, "unknown key"),
])
def test_bad_values_are_refused(data, message):
    with pytest.raises(SweepError, match=message):
        Sweep(data, source="t.yaml")


def test_missing_file_is_named():
    with pytest.raises(SweepError, match="cannot read the sweep file /nope.yaml"):
        load("/nope.yaml")


@pytest.mark.parametrize("name", sorted(f for f in os.listdir(SWEEPS) if f.endswith(".yaml")))
def test_shipped_sweeps_load(name):
    s = load(os.path.join(SWEEPS, name), root="/ws")
    assert s.name == os.path.splitext(name)[0]
    assert s.trials and s.result["file"]


def test_set_fixed_changes_every_trial_and_refuses_others():
    s = load(os.path.join(FIX, "sweep_ok.yaml"))
    s.set_fixed("v0", "2.5")
    assert all(t.params["v0"] == 2.5 for t in s.trials) and len(s.trials) == 12
    with pytest.raises(SweepError, match="--set mu: only fixed parameters can be set"):
        s.set_fixed("mu", "1")

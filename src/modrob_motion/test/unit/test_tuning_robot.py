"""Tier 1: tune_robot tunes every joint of a URDF robot in the ODE core in turn and keeps a joint's
new gains only if steps settle in the check configurations too; tune_pid --all writes the table that
modrob_build takes its default gains from."""
import os
import subprocess
import sys

import pytest
import yaml

from modrob_sim.tuning.robot import default_configs, step_check, tune_robot

HERE = os.path.dirname(os.path.abspath(__file__))
TWO_LINK = os.path.normpath(os.path.join(HERE, "..", "..", "..", "modrob_description", "urdf",
                                         "two_link_test.urdf"))
SLUGGISH = {"joint1": {"p": 20.0, "i": 0.0, "d": 2.0, "i_clamp": 0.0},
            "joint2": {"p": 30.0, "i": 10.0, "d": 2.0, "i_clamp": 2.0}}


@pytest.fixture(scope="module")
def urdf_path(tmp_path_factory):
    """The two-link test arm bolted to the world (as a Gazebo robot needs a 'world' link to stand)."""
    with open(TWO_LINK) as fh:
        text = fh.read()
    text = text.replace('<link name="base_link">', '<link name="world"/>\n  <joint name="world_joint" '
                        'type="fixed"><parent link="world"/><child link="base_link"/></joint>\n'
                        '  <link name="base_link">', 1)
    path = tmp_path_factory.mktemp("robot") / "two_link_test.urdf"
    path.write_text(text)
    return str(path)


@pytest.fixture(scope="module")
def urdf(urdf_path):
    with open(urdf_path) as fh:
        return fh.read()


@pytest.fixture(scope="module")
def tuned(urdf):
    return tune_robot(urdf, SLUGGISH, ["joint1", "joint2"], at={"joint2": 0.6})


def test_configs_are_distinct_and_inside_the_limits(urdf):
    configs = default_configs(urdf, ["joint1", "joint2"], {"joint2": 0.6})
    assert [c[0] for c in configs] == ["tuning pose", "zeros", "random"]
    assert configs[0][1] == {"joint2": 0.6}
    rnd = configs[2][1]
    assert -0.61 * 2.0 <= rnd["joint2"] <= 0.61 * 2.0 and -0.61 * 3.14 <= rnd["joint1"] <= 0.61 * 3.14
    assert rnd != configs[1][1]
    assert default_configs(urdf, ["joint1", "joint2"], {"joint2": 0.6}) == configs    # seeded
    assert len(default_configs(urdf, ["joint1", "joint2"], {})) == 2      # tuning pose == zeros


def test_every_joint_is_tuned_and_kept_only_if_it_passes_everywhere(urdf, tuned):
    gains, outcomes = tuned
    assert [o.joint for o in outcomes] == ["joint1", "joint2"]
    for o in outcomes:
        assert o.result is not None and len(o.checks) == 5, o.reason   # large step, sine, 3 poses
        if o.accepted:
            assert gains[o.joint] == o.result.gains
            assert [c[0] for c in o.checks] == ["large step", "fast sine", "tuning pose", "zeros", "random"]
            sine_new, sine_old = o.checks[1][1:]
            assert sine_new.amplitude_ratio >= min(0.8, sine_old.amplitude_ratio)
            for label, new, old in o.checks[:1] + o.checks[2:]:
                # settles inside the 1.8 s watched, overshoot <= 15 % or no worse than before
                assert new.settling_time < 1.8, (o.joint, label, new)
                assert new.overshoot <= max(0.15, old.overshoot) + 1e-9, (o.joint, label, new, old)
            assert o.result.after.iae < o.result.before.iae or (
                o.result.sine_after.rms_error < o.result.sine_before.rms_error)
        else:
            # the reason names the configuration that failed; the current gains stay
            assert gains[o.joint] == SLUGGISH[o.joint]
            failed = [label for label, new, _ in o.checks
                      if label != "fast sine" and (new.overshoot > 0.15 or new.settling_time == float("inf"))]
            assert failed and all(label in o.reason for label in failed), o.reason
    # the shoulder (joint1) is tuned: its sluggish gains give way
    assert outcomes[0].accepted, outcomes[0].reason
    assert gains["joint1"] != SLUGGISH["joint1"]


def test_gains_failing_the_check_are_not_kept(urdf):
    # an overshoot limit nobody can meet (negative): the tuned gains are rejected, with the reason
    gains, outcomes = tune_robot(urdf, SLUGGISH, ["joint2"], at={"joint2": 0.6}, refine=False,
                                 max_overshoot=-1.0)
    assert gains["joint2"] == SLUGGISH["joint2"]
    assert not outcomes[0].accepted and "overshoot" in outcomes[0].reason


def test_step_check_steps_towards_the_middle_of_the_range(urdf):
    m = step_check(urdf, "joint2", SLUGGISH, {"joint2": 1.95})     # +0.1 would hit the 2.0 limit
    assert m.overshoot < 5.0 and m.iae > 0


def test_cli_all_writes_yaml_plots_and_table(tmp_path, urdf_path):
    ctrl = tmp_path / "ctrl.yaml"
    ctrl.write_text(yaml.safe_dump({"bot": {
        "%s_position_controller" % j: {"type": "effort_controllers/JointPositionController", "joint": j,
                                       "pid": g} for j, g in SLUGGISH.items()}}))
    table = tmp_path / "table.yaml"
    from modrob_motion.tune_pid import main
    code = main(["--urdf", urdf_path, "--controllers", str(ctrl), "--all", "--at", "joint2=0.6",
                 "--out", str(tmp_path / "out"), "--table", str(table)])
    assert code == 0
    out = yaml.safe_load((tmp_path / "out" / "bot_gains.yaml").read_text())
    assert set(out["bot"]) == {"joint1_position_controller", "joint2_position_controller"}
    assert (tmp_path / "out" / "bot_joint2_step.png").stat().st_size > 10000
    entry = yaml.safe_load(table.read_text())["robots"]["two_link_test.urdf"]
    assert "joint1" in entry     # only the joints whose tuned gains passed the checks
    assert set(entry["joint1"]["checked"]) == {"large step", "fast sine", "tuning pose", "zeros", "random"}


def test_cli_refuses_a_robot_without_controllers(tmp_path, urdf_path):
    r = subprocess.run([sys.executable, "-c", "import sys; from modrob_motion.tune_pid import main; "
                        "sys.exit(main(sys.argv[1:]))", "--urdf", urdf_path, "--all", "--out", str(tmp_path)],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "no arm joint with a PID controller" in r.stderr

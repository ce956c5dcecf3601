"""tune_pid --search ray: Ray Tune over one joint's gains on a local Ray, the current gains as the
first point, ASHA stopping after the step stage; the YAML the build reads is written."""
import os

import pytest
import yaml

from modrob_sweep import SweepError
from modrob_sweep import tune_search

pytest.importorskip("ray.tune")


def test_default_space_and_overrides():
    sp = tune_search.default_space({"p": 200.0, "i": 0.0, "d": 10.0}, {"d": (1.0, 20.0)})
    assert sp == {"p": (50.0, 800.0), "d": (1.0, 20.0)}
    assert tune_search.default_space({"p": 100.0, "i": 5.0, "d": 2.0})["i"] == (0.0, 20.0)
    with pytest.raises(SweepError, match="p=0:10"):
        tune_search.default_space({"p": 1.0}, {"p": (0.0, 10.0)})
    assert tune_search.parse_space("p=1:2, joint2.d=0.5:3") == {None: {"p": (1.0, 2.0)},
                                                                "joint2": {"d": (0.5, 3.0)}}
    with pytest.raises(SweepError, match="key=lo:hi"):
        tune_search.parse_space("p=1")


def test_tune_pid_search_ray_writes_gains_never_worse(tmp_path, capsys):
    from modrob_motion.tune_pid import main
    out = str(tmp_path / "tune")
    rc = main(["--order", "59,3,55,63,57,5", "--joint", "joint2", "--at", "joint2=0.5", "--search", "ray",
               "--samples", "4", "--workers", "2", "--seed", "1", "--out", out])
    text = capsys.readouterr().out
    assert rc == 0, text
    assert "4 gain sets tried" in text
    with open(os.path.join(out, "modrob0_gains.yaml")) as fh:
        data = yaml.safe_load(fh)
    pid = data["modrob0"]["joint2_position_controller"]["pid"]
    ctrl = data["modrob0"]["joint2_position_controller"]
    assert ctrl["type"] == "effort_controllers/JointPositionController"
    assert pid["p"] > 0 and pid["d"] > 0
    line = [ln for ln in text.splitlines() if ln.strip().startswith("joint2") and " -> " in ln][0]
    before, after = (float(v) for v in line.split("cost")[1].split("(")[0].split("->"))
    assert after <= before
    assert os.path.getsize(os.path.join(out, "modrob0_joint2_step.png")) > 1000

"""Tier 1: tune_pid merges tuned gains into modrob_build's table, per module order and joint."""
import pytest
import yaml

from modrob_motion.tune_pid import update_gains_table
from modrob_sim.tuning import TuningError


def test_gains_table_merge_and_bad_yaml(tmp_path):
    path = str(tmp_path / "gains.yaml")
    update_gains_table(path, "59,3,55,63,57,5", "joint1", {"p": 1.0, "i": 0.0, "d": 0.1}, {"method": "x"})
    update_gains_table(path, "59,3,55,63,57,5", "joint2", {"p": 2.0, "i": 0.0, "d": 0.2}, {"method": "y"})
    table = yaml.safe_load(open(path))
    assert set(table["robots"]["59,3,55,63,57,5"]) == {"joint1", "joint2"}
    assert table["robots"]["59,3,55,63,57,5"]["joint2"]["method"] == "y"
    assert open(path).read().startswith("# PID gains tuned by `rosrun modrob_motion tune_pid`")
    (tmp_path / "bad.yaml").write_text("robots: [unclosed")
    with pytest.raises(TuningError, match="not valid YAML"):
        update_gains_table(str(tmp_path / "bad.yaml"), "k", "j", {"p": 1.0}, {})

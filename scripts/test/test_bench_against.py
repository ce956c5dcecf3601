"""scripts/bench/against.py (make bench AGAINST=<commit>): how a pair's ratio is read, which goals
apply, and that a unit runs in the other workspace's own environment, not in ours."""
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "bench"))
import against  # noqa: E402


def test_a_rate_is_better_higher_and_a_time_lower():
    runs = {"bulbs_one": [({"sim_per_wall": 8.0, "scenario_wall": 3.0},
                           {"sim_per_wall": 4.0, "scenario_wall": 6.0}),
                          ({"sim_per_wall": 9.0, "scenario_wall": 2.0},
                           {"sim_per_wall": 9.0, "scenario_wall": 4.0})]}
    rate, time_ = against.figures(runs, reference=False)
    assert rate.ratio["values"] == [2.0, 1.0]
    assert time_.ratio["values"] == [2.0, 2.0]          # theirs / ours: a shorter task is better
    assert rate.ours["values"] == [8.0, 9.0] and rate.peer["values"] == [4.0, 9.0]


def test_goals_only_against_the_reference_commit():
    runs = {"polaris_pace": [({"sim_per_wall": 12.0, "node_loop_thread_per_sim_s": 0.05},
                              {"sim_per_wall": 4.0, "node_loop_thread_per_sim_s": 0.125})]}
    pace, loop = against.figures(runs, reference=True)
    assert pace.verdict() == "meets >=3x"
    assert loop.verdict() == ""                         # no goal on the loop thread
    runs["polaris_pace"][0][1]["sim_per_wall"] = 4.5
    assert against.figures(runs, reference=True)[0].verdict() == "MISSES >=3x"
    assert against.figures(runs, reference=False)[0].verdict() == ""


def test_a_failed_side_drops_its_pair():
    runs = {"ptrz_pace": [({"sim_per_wall": 10.0}, {"error": "exit 1: no master"}),
                          ({"sim_per_wall": 12.0}, {"sim_per_wall": 3.0})]}
    (pace,) = against.figures(runs, reference=False)
    assert pace.ratio["values"] == [4.0]


def test_a_unit_runs_in_its_workspace_environment(tmp_path, monkeypatch):
    ws = tmp_path / "ws"
    (ws / "scripts" / "bench").mkdir(parents=True)
    # the workspace's env.sh sets what its units see; ours must not leak in
    (ws / "scripts" / "env.sh").write_text("export MODROB_WS_MARK=theirs\n")
    (ws / "scripts" / "bench" / "units.py").write_text(
        "import json, os, sys\n"
        "args = sys.argv[1:]\n"
        "out = args[args.index('--json') + 1]\n"
        "json.dump({'unit': args[0], 'seconds': args[args.index('--seconds') + 1],\n"
        "           'mark': os.environ.get('MODROB_WS_MARK'), 'leak': os.environ.get('MODROB_LEAK_CHECK'),\n"
        "           'load_avg': 0.0}, open(out, 'w'))\n")
    monkeypatch.setenv("MODROB_LEAK_CHECK", "ours")
    res = against.run_unit(str(ws), "ptrz_pace", 8.0, 1, str(tmp_path / "r.json"))
    assert res["unit"] == "ptrz_pace" and res["seconds"] == "8.0"
    assert res["mark"] == "theirs"
    assert res["leak"] is None


def test_a_unit_that_fails_says_why(tmp_path):
    ws = tmp_path / "ws"
    (ws / "scripts" / "bench").mkdir(parents=True)
    (ws / "scripts" / "env.sh").write_text("")
    (ws / "scripts" / "bench" / "units.py").write_text("import sys\nsys.exit('no master came up')\n")
    res = against.run_unit(str(ws), "katana_pace", 0.0, 1, str(tmp_path / "r.json"))
    assert res["error"].startswith("exit 1") and "no master came up" in res["error"]
    json.dumps(res)

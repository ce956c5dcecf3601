"""Benchmark of the lap (scripts/bench/polaris_lap.sh): one full lap without obstacles, then
``runs`` seeded runs with a street cone placed on the lap; each must stop before touching it.
The seeded runs are the trials of the sweep modrob_sweep/sweeps/polaris_cones.yaml on a local Ray
(``--workers`` side by side; docs/sweeps.md), each ``lap_bench --one SEED --out DIR``, which
writes lap_run.json. Writes lap_paths.png and lap_bench.md into ``--out``, the sweep's table,
summary, plots and trial folders into ``--sweep-out`` (default ``--out``/sweep/; the bench script
keeps them out of the docs, in the workspace's out/bench/)."""
import argparse
import json
import os
import sys
import time

from polaris_description import parking_lot
from polaris_description.lap import run_lap, seeded_cone

RUN_FILE = "lap_run.json"


def one_run(seed, out):
    """One seeded cone run: stops before the cone without leaving the path (lap_run.json)."""
    cone = seeded_cone(seed)
    r = run_lap(cone=cone, seed=seed)
    good = bool(r["stopped"] and r["min_gap"] > 0.0 and r["max_cross_track"] < 1.0)
    det = r["detected_at"]
    res = {"success": good, "seed": seed, "cone": list(cone), "stopped": bool(r["stopped"]),
           "detected_ahead": None if det is None else float(det[1]), "min_gap": float(r["min_gap"]),
           "max_cross_track": float(r["max_cross_track"]), "sim_time": float(r["samples"][-1]["t"]),
           "samples": [{"x": float(p["x"]), "y": float(p["y"])} for p in r["samples"]]}
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, RUN_FILE), "w") as fh:
        json.dump(res, fh)
    print("RESULT seed %d: cone at (%.2f, %.2f): %s, clearance %.2f m, max path error %.2f m"
          % (seed, cone[0], cone[1], "stopped" if r["stopped"] else "DID NOT STOP", r["min_gap"],
             r["max_cross_track"]), flush=True)
    return 0 if good else 1


def cone_runs(runs, workers, folder):
    """The seeded runs as sweep trials in ``folder``; their lap_run.json contents in seed order."""
    from modrob_sweep import results
    from modrob_sweep.runner import run
    from modrob_sweep.cli import find_file
    from modrob_sweep.spec import load
    sweep = load(find_file("polaris_cones.yaml"), runs=runs)
    rows, interrupted = run(sweep, folder, workers=workers)
    if interrupted:
        raise KeyboardInterrupt()
    results.write_all(rows, folder, sweep.name, sweep.parameter_names, sweep.varying(),
                      sweep.result["metrics"])
    got = []
    for row in sorted(rows, key=lambda r: r["seed"]):
        path = os.path.join(row["out"], RUN_FILE) if row["out"] else ""
        if row["outcome"] in ("success", "failure") and os.path.exists(path):
            with open(path) as fh:
                got.append(json.load(fh))
        else:
            seed = int(row["seed"])
            got.append({"success": False, "seed": seed, "cone": list(seeded_cone(seed)), "stopped": False,
                        "detected_ahead": None, "min_gap": float("nan"), "max_cross_track": float("nan"),
                        "samples": [], "why": "%s: %s" % (row["outcome"], row["detail"])})
    return got


def main(argv=None):
    from polaris_description.figures import path_plot
    from matplotlib.patches import Rectangle
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", required=True)
    p.add_argument("--runs", type=int, default=10)
    p.add_argument("--workers", type=int, default=1, help="seeded runs side by side")
    p.add_argument("--sweep-out", default=None, help="the sweep's folder (default: OUT/sweep)")
    p.add_argument("--one", type=int, default=None, metavar="SEED", help="only the cone run of this seed")
    a = p.parse_args(argv)
    if a.one is not None:
        return one_run(a.one, a.out)
    os.makedirs(a.out, exist_ok=True)
    runs = []
    t0 = time.time()
    lap = run_lap(cone=None)
    print("lap: completed %s, max distance from the path %.2f m, %.1f s simulated (%.0f s wall)"
          % (lap["completed"], lap["max_cross_track"], lap["samples"][-1]["t"], time.time() - t0), flush=True)
    runs.append(("lap without obstacle", lap["samples"]))
    done = cone_runs(a.runs, a.workers, a.sweep_out or os.path.join(a.out, "sweep"))
    ok = sum(r["success"] for r in done)
    cones = [tuple(r["cone"]) for r in done]
    rows = [(r["seed"], tuple(r["cone"]), r["detected_ahead"], r["min_gap"], r["max_cross_track"],
             r["success"]) for r in done]
    for r in done:
        runs.append(("seed %d" % r["seed"], r["samples"]))
    wps = parking_lot.lap_waypoints(1.0)

    def extra(ax):
        ax.plot([w[0] for w in wps], [w[1] for w in wps], "k.", ms=3, label="waypoints")
        ax.plot([c[0] for c in cones], [c[1] for c in cones], "^", color="orange", ms=8,
                label="cones (seeds)")
        for r in parking_lot.RAMPS:
            x0, x1 = parking_lot.ramp_extent(r)
            ax.add_patch(Rectangle((x0, r.y - r.width / 2), x1 - x0, r.width, color="grey", alpha=0.4))
    path_plot(runs, os.path.join(a.out, "lap_paths.png"), title="Lap and %d seeded cone runs" % a.runs,
              extra=extra)
    with open(os.path.join(a.out, "lap_bench.md"), "w") as f:
        f.write("| seed | cone (x, y) | detected (m ahead of the bumper) | clearance at stop [m] | "
                "max path error [m] | ok |\n|---|---|---|---|---|---|\n")
        for seed, cone, det, gap, ct, good in rows:
            f.write("| %d | (%.2f, %.2f) | %s | %.2f | %.2f | %s |\n"
                    % (seed, cone[0], cone[1], "-" if det is None else "%.2f" % det, gap, ct,
                       "yes" if good else "NO"))
    print("RESULT: lap %s (max path error %.2f m); cone stops %d/%d"
          % ("completed" if lap["completed"] else "NOT completed", lap["max_cross_track"], ok, a.runs))
    return 0 if lap["completed"] and ok == a.runs else 1


if __name__ == "__main__":
    sys.exit(main())

"""Benchmark of the lap (scripts/bench/polaris_lap.sh): one full lap without obstacles, then
``runs`` seeded runs with a street cone placed on the lap; each must stop before touching it.
Writes lap_paths.png and lap_bench.md into ``--out``."""
import argparse
import os
import sys
import time

from polaris_description import parking_lot
from polaris_description.lap import run_lap, seeded_cone


def main(argv=None):
    from polaris_description.figures import path_plot
    from matplotlib.patches import Rectangle
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", required=True)
    p.add_argument("--runs", type=int, default=10)
    a = p.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    rows, runs = [], []
    t0 = time.time()
    lap = run_lap(cone=None)
    print("lap: completed %s, max distance from the path %.2f m, %.1f s simulated (%.0f s wall)"
          % (lap["completed"], lap["max_cross_track"], lap["samples"][-1]["t"], time.time() - t0), flush=True)
    runs.append(("lap without obstacle", lap["samples"]))
    ok = 0
    cones = []
    for seed in range(1, a.runs + 1):
        cone = seeded_cone(seed)
        cones.append(cone)
        t0 = time.time()
        r = run_lap(cone=cone, seed=seed)
        good = r["stopped"] and r["min_gap"] > 0.0 and r["max_cross_track"] < 1.0
        ok += good
        det = r["detected_at"]
        rows.append((seed, cone, det, r["min_gap"], r["max_cross_track"], good))
        runs.append(("seed %d" % seed, r["samples"]))
        print("seed %2d: cone at (%.2f, %.2f): %s, detected %s, clearance %.2f m, max path error %.2f m "
              "(%.0f s wall)"
              % (seed, cone[0], cone[1], "stopped" if r["stopped"] else "DID NOT STOP",
                 "-" if det is None else "%.2f m ahead at t %.1f s" % (det[1], det[0]), r["min_gap"],
                 r["max_cross_track"], time.time() - t0), flush=True)
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
                    % (seed, cone[0], cone[1], "-" if det is None else "%.2f" % det[1], gap, ct,
                       "yes" if good else "NO"))
    print("RESULT: lap %s (max path error %.2f m); cone stops %d/%d"
          % ("completed" if lap["completed"] else "NOT completed", lap["max_cross_track"], ok, a.runs))
    return 0 if lap["completed"] and ok == a.runs else 1


if __name__ == "__main__":
    sys.exit(main())

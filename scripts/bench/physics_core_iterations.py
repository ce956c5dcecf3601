#!/usr/bin/env python3
"""Solver work behind the physics core ratios: our ODE core (every body awake) and PyBullet on the
scene of physics_core.py at the same FORCED number of solver iterations (PyBullet's early exit
off: solverResidualThreshold 0), and PyBullet as it runs by default (early exit at residual 1e-7,
numSolverIterations 50 as an upper bound). Not a test; prints a Markdown table.

    bash scripts/bench/physics_core_iterations.sh [--steps N] [--repeat R] [--iters 5,10,20,50]

Steps per CPU second (best of --repeat interleaved runs), the cans' drift and the arm's error over
the timed steps, so that what fewer iterations cost in accuracy is beside what they save.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import physics_core as scene  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=5000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--iters", default="5,10,20,50")
    args = ap.parse_args()
    try:
        iters = [int(x) for x in args.iters.split(",") if x.strip()]
    except ValueError:
        ap.error("--iters takes comma-separated integers, got %r" % args.iters)
    if not iters or min(iters) < 1:
        ap.error("--iters needs at least one count >= 1")
    files = scene.scene_files("modrob_bench_")
    runs = [("PyBullet default (early exit)", None,
             lambda: scene.run_pybullet(args.steps, files))]
    for n in iters:
        runs.append(("ours, %d iterations" % n, n,
                     lambda n=n: scene.run_ours(args.steps, None, auto_disable=False, iters=n)))
        runs.append(("PyBullet, %d iterations forced" % n, n,
                     lambda n=n: scene.run_pybullet(args.steps, files, residual_threshold=0.0, iters=n)))
    best = {}
    for r in range(args.repeat):  # interleaved, so that a busy stretch hits every row alike
        for name, _n, fn in runs:
            res = fn()
            if name not in best or res["steps_per_s"] > best[name]["steps_per_s"]:
                best[name] = res
            print("[bench] run %d %-32s %8.0f steps per CPU s" % (r + 1, name, res["steps_per_s"]),
                  file=sys.stderr, flush=True)
    ref = best["PyBullet default (early exit)"]["steps_per_s"]
    print("| engine, solver iterations | steps per CPU s (best of %d) | vs PyBullet default | "
          "vs PyBullet at the same forced iterations | can drift (m) | arm error (rad) |" % args.repeat)
    print("|---|---|---|---|---|---|")
    for name, n, _fn in runs:
        r = best[name]
        same = ""
        if name.startswith("ours"):
            same = "%.2fx" % (r["steps_per_s"] / best["PyBullet, %d iterations forced" % n]["steps_per_s"])
        print("| %s | %.0f | %.2fx | %s | %.1e | %.1e |" % (name, r["steps_per_s"], r["steps_per_s"] / ref,
                                                            same, r["can_drift_m"], r["arm_err_rad"]))


if __name__ == "__main__":
    main()

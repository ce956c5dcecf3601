#!/usr/bin/env python3
"""Bulbs and Slides benchmark: N runs of the one-robot pick-and-place with the bulb's start pose
jittered by up to --jitter metres (seed = run number): the sweep
src/modrob_sweep/sweeps/bulbs_and_slides_jitter.yaml on a local Ray (docs/sweeps.md), each trial a
bulbs_and_slides_demo. Prints every run, the success rate, the real-time factor and the bulb's
offset from the grasp centre once it is at rest after the lift (a lift that loses the bulb reads
more than 20 mm), and writes them into docs/benchmarks.md under "## Bulbs and Slides" (only that
section is replaced). The sweep's table, summary and plots go to --out; each run's folder there
(trials/<NN>/) keeps its plot, bag, result YAML and console log (trial.log).

    python3 scripts/bench/bulbs_and_slides.py [--runs 20] [--jitter 0.004] [--scenario one_robot] [-j N]
Passes when at least --need runs succeed (default 19 of 20). -j N runs N demos side by side (each
starts its own ROS master on a free port); the outcome of a run does not depend on its neighbours
(everything runs on simulated time), only its wall time does. -j 1,2 runs the whole benchmark once
per worker count, one after the other, and adds the wall times and trials per hour of each to the
section (the sweep runner's throughput).
"""
import argparse
import math
import os
import re
import statistics
import subprocess
import sys
import time

import yaml

from modrob_motion.bulbs_and_slides.scenario import LIFT_LOST
from modrob_sweep import results
from modrob_sweep.runner import run
from modrob_sweep.spec import Sweep

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SWEEP_FILE = os.path.join(ROOT, "src", "modrob_sweep", "sweeps", "bulbs_and_slides_jitter.yaml")


def make_sweep(scenario, jitter, runs):
    """The shipped sweep file, for this scenario, jitter and number of runs."""
    with open(SWEEP_FILE) as fh:
        data = yaml.safe_load(fh)
    data["scenario"]["demo"] = scenario
    data["result"]["file"] = "bulbs_and_slides_%s_result.yaml" % scenario
    data["parameters"]["fixed"]["jitter"] = jitter
    data["repetitions"] = runs
    if scenario != "one_robot":
        data["name"] = "bulbs_and_slides_%s_jitter" % scenario
    return Sweep(data, source=SWEEP_FILE, root=ROOT)


def run_sweep(sweep, out, workers):
    """Rows by run number, and the sweep's wall time; the table, summary and plots under ``out``."""
    t0 = time.monotonic()
    rows, interrupted = run(sweep, out, workers=workers)
    wall = time.monotonic() - t0
    if interrupted:
        raise KeyboardInterrupt()
    results.write_all(rows, out, sweep.name, sweep.parameter_names, sweep.varying(), sweep.result["metrics"],
                      {"workers": workers, "wall time": "%.0f s" % wall})
    return {r["trial"]: r for r in rows}, wall


def throughput_text(throughput, runs):
    """The runner's figures: wall time and trials per hour per worker count, and what N machines
    of this kind would do at the measured per-trial cost."""
    parts, best = [], None
    for workers, wall, n, ok in throughput:
        per_hour = 3600.0 * n / wall if wall > 0 else 0.0
        parts.append("%d worker%s: %.0f s for %d trials (%d succeeded), %.0f trials per hour"
                     % (workers, "" if workers == 1 else "s", wall, n, ok, per_hour))
        if best is None or per_hour > best[1]:
            best = (workers, per_hour)
    text = ("Sweep runner (modrob_sweep on a local Ray, trials side by side, one after the other in the "
            "same run): " + "; ".join(parts) + ".")
    if best and len(throughput) > 1:
        text += (" On paper, N machines like this one on a Ray cluster, each running %d trials at once, make "
                 "about N x %.0f trials per hour (the trials do not talk to each other; the driver only "
                 "collects one table row per trial): 4 machines about %.0f, 16 about %.0f."
                 % (best[0], best[1], 4 * best[1], 16 * best[1]))
    return text


def write_section(text):
    path = os.path.join(ROOT, "docs", "benchmarks.md")
    old = open(path).read() if os.path.exists(path) else "# Benchmarks\n"
    section = "## Bulbs and Slides\n\n" + text.rstrip() + "\n"
    pat = re.compile(r"^## Bulbs and Slides\n.*?(?=^## |\Z)", re.S | re.M)
    new = pat.sub(section + "\n", old) if pat.search(old) else old.rstrip() + "\n\n" + section
    with open(path, "w") as fh:
        fh.write(new)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=20)
    p.add_argument("--jitter", type=float, default=0.004)
    p.add_argument("--scenario", default="one_robot")
    p.add_argument("--need", type=int, default=None)
    p.add_argument("--out", default=os.path.join(ROOT, "out", "bench_bulbs_and_slides"))
    p.add_argument("--no-doc", action="store_true")
    p.add_argument("-j", "--jobs", default="1",
                   help="runs side by side, each with its own ROS master; 1,2 = the benchmark once per count")
    p.add_argument("--note", default="", help="a sentence added to the docs section (conditions of the run)")
    args = p.parse_args()
    try:
        counts = [int(v) for v in args.jobs.split(",")]
    except ValueError:
        p.error("-j takes a number of workers or a list such as 1,2; got %r" % args.jobs)
    if any(c < 1 for c in counts):
        p.error("-j: every worker count must be at least 1")
    need = args.need if args.need is not None else int(round(0.95 * args.runs))
    sweep = make_sweep(args.scenario, args.jitter, args.runs)
    throughput = []
    for workers in counts:
        out = args.out if len(counts) == 1 else os.path.join(args.out, "j%d" % workers)
        done, sweep_wall = run_sweep(sweep, out, workers)
        succeeded = sum(r["outcome"] == "success" for r in done.values())
        throughput.append((workers, sweep_wall, len(done), succeeded))
    rows, ok, sim, wall_sim, lifts = [], 0, 0.0, 0.0, []
    for k in range(args.runs):
        r = done[k]
        good = r["outcome"] == "success"
        ok += bool(good)
        if not math.isnan(r["sim_s"]):
            sim += r["sim_s"]
            wall_sim += r.get("wall_time", 0.0) or 0.0
        lift = r.get("lift_offset", float("nan"))
        if isinstance(lift, float) and not math.isnan(lift):
            lifts.append(lift)
        message = r.get("message")
        message = message if isinstance(message, str) else "%s (%s)" % (r["outcome"], r["detail"])
        rows.append("| %d | %s | %.1f | %.1f | %.2f | %.1f | %.1f | %s |" % (
            k, "yes" if good else "no", r["sim_s"], r["wall_s"], r.get("grasp_force", float("nan")),
            1000 * lift, 1000 * r.get("placement_error", float("nan")), message.replace("|", "/")[:80]))
    rtf = sim / wall_sim if wall_sim > 0 else 0.0
    summary = ("%s: %d/%d succeeded (need %d), real-time factor %.2f (simulated %.0f s in %.0f s of scenario "
               "wall time)" % (args.scenario, ok, args.runs, need, rtf, sim, wall_sim))
    if lifts:
        summary += ("; the bulb's offset from the grasp centre after the lift: median %.1f mm, %d of %d "
                    "above 5 mm, largest %.1f mm (lost above %.0f mm)"
                    % (1000 * statistics.median(lifts), sum(v > 0.005 for v in lifts), len(lifts),
                       1000 * max(lifts), 1000 * LIFT_LOST))
    lags = [r["js_lag"] for r in done.values() if isinstance(r.get("js_lag"), float)
            and not math.isnan(r["js_lag"])]
    if lags:
        summary += ("; joint_states reached the scenario up to %.2f s of simulated time late (median of "
                    "the runs' latest, largest %.2f s)" % (statistics.median(lags), max(lags)))
    print(summary)
    runner = throughput_text(throughput, args.runs)
    print(runner)
    if not args.no_doc:
        rev = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                             text=True).stdout.strip()
        text = ("Command: `bash scripts/bench/bulbs_and_slides.sh` (%d runs of `bulbs_and_slides_demo "
                "--scenario %s --jitter %g --seed <run> --no-streams`: the bulb at the red tip is moved by "
                "up to %g mm "
                "along and across the slide before the pick). Measured %s, commit %s, on this 2-core "
                "machine.\n\n"
                "**%s**\n\n| run | success | sim time (s) | wall time incl. start-up (s) | grasp force (N) | "
                "bulb off the grasp centre after the lift (mm) | placement error (mm) | message |\n"
                "|---|---|---|---|---|---|---|---|\n%s\n"
                % (args.runs, args.scenario, args.jitter, 1000 * args.jitter, time.strftime("%Y-%m-%d"), rev,
                   summary, "\n".join(rows)))
        write_section(text + "\n" + runner + "\n" + ("\n" + args.note + "\n" if args.note else ""))
    return 0 if ok >= need else 1


if __name__ == "__main__":
    sys.exit(main())

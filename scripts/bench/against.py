#!/usr/bin/env python3
"""`make bench AGAINST=<commit>`: the scenario launches' pace units of this workspace against the
same units in another commit's workspace, pair by pair, and their ratios.

    bash scripts/bench/run.sh --against 32ef8e1 [--pairs 3] [--only polaris_pace,bulbs_one]

The other commit is checked out as a git worktree under out/bench/against/<commit>/ and built
there once (`make build`, a few minutes; kept for the next run). The units measure the workspace
they run in (its ROS_PACKAGE_PATH, its scripts/gazebo), so this workspace's scripts/bench/units.py
and the files it imports are copied into the worktree's scripts/bench/ and run there: both sides
are measured by the same code. Each unit runs once in each workspace per pair, the order
alternating from pair to pair (a busy stretch of the machine then hits both alike), each in a
clean environment that sourced its workspace's scripts/env.sh. A pair's ratio says how many times
better this workspace did (ours / theirs for a rate, theirs / ours for a time); the table gives
each figure's median (min - max) per side and of the ratios. JSON with every run:
out/bench/against_<commit>.json.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from run import Figure, fmt, machine  # noqa: E402

#: the files of scripts/bench/ that units.py needs beside it
UNIT_FILES = ("units.py", "procs.py", "physics_core.py")

#: unit -> (its --seconds, [(result key, what it is, higher is better)])
UNITS = {
    "polaris_pace": (8.0, [("sim_per_wall", "Polaris (polaris.launch), simulated s per wall s", True),
                           ("node_loop_thread_per_sim_s",
                            "Polaris, the simulation loop thread's CPU s per simulated s", False)]),
    "katana_pace": (0.0, [("sim_per_wall", "Katana stacking (katana_stack.launch), simulated s per wall s",
                           True)]),
    "ptrz_pace": (8.0, [("sim_per_wall",
                         "PTRZ, 3 cameras (ptrz.launch images:=false), simulated s per wall s", True)]),
    "bulbs_one": (0.0, [("sim_per_wall", "Bulbs and Slides one robot, simulated s per wall s", True),
                        ("scenario_wall", "Bulbs and Slides one robot, the task's wall s", False)]),
}

#: the commit before the one step loop and the goals of its comparison (docs/benchmarks.md)
REFERENCE = "32ef8e1"
REFERENCE_GOALS = {("polaris_pace", "sim_per_wall"): 3.0, ("katana_pace", "sim_per_wall"): 2.0,
                   ("ptrz_pace", "sim_per_wall"): 2.0, ("bulbs_one", "sim_per_wall"): 1.0}


def git(*args, cwd=ROOT):
    proc = subprocess.run(["git", "-C", cwd] + list(args), capture_output=True, text=True, check=True)
    return proc.stdout.strip()


def workspace(commit, log):
    """The other commit's built workspace (made and built on first use); returns its path."""
    sha = git("rev-parse", "--verify", commit + "^{commit}")
    path = os.path.join(ROOT, "out", "bench", "against", sha[:12])
    stamp = os.path.join(path, ".bench-built")
    if not os.path.isdir(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        git("worktree", "prune")
        print("[against] git worktree add %s %s" % (os.path.relpath(path, ROOT), sha[:12]), flush=True)
        git("worktree", "add", "--detach", path, sha)
    if not os.path.exists(stamp):
        print("[against] building %s (make build, a few minutes; log: %s)" % (sha[:12], log), flush=True)
        with open(log, "w") as f:
            rc = subprocess.run(["make", "-C", path, "build"], stdout=f, stderr=subprocess.STDOUT,
                                env=clean_env()).returncode
        if rc != 0:
            raise SystemExit("[against] make build of %s failed (exit %d): see %s" % (sha[:12], rc, log))
        with open(stamp, "w") as f:
            f.write(sha + "\n")
    for name in UNIT_FILES:
        shutil.copy2(os.path.join(HERE, name), os.path.join(path, "scripts", "bench", name))
    return path


def clean_env():
    """The environment of a fresh login shell: nothing of this workspace's ROS, venv or paths."""
    keep = ("HOME", "USER", "LOGNAME", "LANG", "LC_ALL", "TERM", "TMPDIR", "DISPLAY")
    env = {k: os.environ[k] for k in keep if k in os.environ}
    env["PATH"] = "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin"
    return env


def run_unit(ws, unit, seconds, rep, out):
    """One run of ``unit`` in workspace ``ws``: its result dict, or {"error": ...}."""
    script = 'source "$1/scripts/env.sh" >/dev/null && shift && exec python3 "$@"'
    cmd = ["bash", "-c", script, "bash", ws, os.path.join(ws, "scripts", "bench", "units.py"), unit,
           "--seconds", str(seconds), "--rep", str(rep), "--json", out]
    t0 = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=clean_env(), timeout=1800)
    if proc.returncode != 0 or not os.path.exists(out):
        return {"error": "exit %d: %s" % (proc.returncode, proc.stderr.strip()[-600:]),
                "wall_s": time.monotonic() - t0}
    with open(out) as f:
        res = json.load(f)
    res["wall_s"] = time.monotonic() - t0
    return res


def figures(runs, reference):
    """The Figures of ``runs`` ({unit: [(ours, theirs) per pair]}): each side's values and the pairs'
    ratios (how many times better ours did), with the reference's goals where they apply."""
    out = []
    for unit, pairs in runs.items():
        for key, label, higher in UNITS[unit][1]:
            ok = [(a[key], b[key]) for a, b in pairs
                  if "error" not in a and "error" not in b and a.get(key) and b.get(key)]
            ours, theirs = [a for a, _ in ok], [b for _, b in ok]
            ratios = [a / b if higher else b / a for a, b in ok]
            goal = REFERENCE_GOALS.get((unit, key)) if reference else None
            out.append(Figure(label, "", ours, None, theirs, ratios, ("ratio", goal) if goal else None))
    return out


def table(figs, meta, other, pairs, load):
    lines = ["Command: `make bench AGAINST=%s` (%d pair%s). Measured %s on %s (%d cores), commit %s "
             "against %s; load average %.1f at the start and %.1f at the end." % (
                 other, pairs, "" if pairs == 1 else "s", meta["date"], meta["cpu"], meta["cores"],
                 meta["commit"], other, load[0], load[1]),
             "Each cell: median (min - max) over the pairs; the ratio is how many times better this "
             "workspace did in each pair (ours / theirs for a rate, theirs / ours for a time).", "",
             "| figure | ours | %s | ratio | pairs | goal |" % other, "|---|---|---|---|---|---|"]
    for f in figs:
        lines.append("| %s | %s | %s | %s | %d | %s |" % (
            f.name, fmt(f.ours), fmt(f.peer), fmt(f.ratio, ratio=True), f.ratio["n"] if f.ratio else 0,
            f.verdict() or "-"))
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--against", required=True, help="the commit to compare with (any git revision)")
    ap.add_argument("--pairs", type=int, default=3, help="runs per unit and workspace (default 3)")
    ap.add_argument("--only", default="", help="comma-separated units: %s" % ", ".join(UNITS))
    args = ap.parse_args(argv)
    units = [u for u in (args.only.split(",") if args.only else UNITS) if u]
    for u in units:
        if u not in UNITS:
            ap.error("unknown unit %r (known: %s)" % (u, ", ".join(UNITS)))
    if args.pairs < 1:
        ap.error("--pairs must be at least 1")
    out = os.path.join(ROOT, "out", "bench")
    os.makedirs(out, exist_ok=True)
    sha = git("rev-parse", "--verify", args.against + "^{commit}")
    theirs = workspace(args.against, os.path.join(out, "against_%s_build.log" % sha[:12]))
    load0, meta, t0 = os.getloadavg()[0], machine(), time.monotonic()
    runs = {u: [] for u in units}
    scratch = os.path.join(out, "against", "runs")
    os.makedirs(scratch, exist_ok=True)
    for i in range(args.pairs):
        for unit in units:
            seconds = UNITS[unit][0]
            pair = {}
            order = ("ours", "theirs") if i % 2 == 0 else ("theirs", "ours")
            for side in order:
                ws = ROOT if side == "ours" else theirs
                out_json = os.path.join(scratch, "%s_%s_%d.json" % (unit, side, i))
                res = run_unit(ws, unit, seconds, i + 1, out_json)
                pair[side] = res
                print("[against] pair %d/%d %s %s: %s" % (
                    i + 1, args.pairs, unit, side,
                    res["error"] if "error" in res
                    else "%.0f s, load %.1f" % (res["wall_s"], res["load_avg"])),
                    flush=True)
            runs[unit].append((pair["ours"], pair["theirs"]))
    figs = figures(runs, sha.startswith(REFERENCE))
    text = table(figs, meta, args.against, args.pairs, (load0, os.getloadavg()[0]))
    print(text)
    print("[against] %.0f s in all" % (time.monotonic() - t0))
    path = os.path.join(out, "against_%s.json" % sha[:12])
    with open(path, "w") as f:
        json.dump({"meta": meta, "against": sha, "figures": [fg.as_dict() for fg in figs],
                   "runs": {u: [{"ours": a, "theirs": b} for a, b in p] for u, p in runs.items()}},
                  f, indent=1)
    print("[against] wrote %s" % os.path.relpath(path, ROOT))
    errors = [r for p in runs.values() for pair in p for r in pair if "error" in r]
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())

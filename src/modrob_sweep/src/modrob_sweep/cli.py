"""``rosrun modrob_sweep sweep FILE`` / ``make sweep FILE=...``: run a sweep file's trials on Ray and
write trials.csv, trials.parquet, summary.md and the plots under out/sweeps/<name>/.

    sweep src/modrob_sweep/sweeps/katana_seeds.yaml                 # this machine, one trial per core
    sweep bulbs_and_slides_jitter.yaml --runs 4 --workers 2         # a file from the package's sweeps/
    sweep pid_search.yaml --address 192.168.1.10:6379               # on a Ray cluster (docs/sweeps.md)

Exit status: 0 when every trial was run and recorded (and --need successes were reached), 1 when
fewer than --need trials succeeded, 2 for a sweep that cannot run as written, 130 after Ctrl-C
(the trials that finished are written).
"""
import argparse
import os
import shutil
import subprocess
import sys
import time

from modrob_sweep import SweepError
from modrob_sweep import results
from modrob_sweep.spec import load


def package_sweeps_dir():
    return os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                        "sweeps")


def find_file(path):
    """A path as given, else a file of that name in the package's sweeps/ folder."""
    if os.path.exists(path):
        return path
    for name in (path, path + ".yaml"):
        cand = os.path.join(package_sweeps_dir(), name)
        if os.path.exists(cand):
            return cand
    shipped = sorted(f for f in os.listdir(package_sweeps_dir()) if f.endswith(".yaml"))
    raise SweepError("no sweep file %s (and none of that name in %s: %s)"
                     % (path, package_sweeps_dir(), ", ".join(shipped)))


def commit(root):
    proc = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    return proc.stdout.strip() or "?"


def prepare_out(folder):
    """A fresh results folder (the previous sweep of that name is replaced)."""
    if os.path.isdir(folder):
        for name in os.listdir(folder):
            p = os.path.join(folder, name)
            if name == "trials" and os.path.isdir(p):
                shutil.rmtree(p)
            elif name.startswith(("trials.", "summary.")) or name.endswith(".png"):
                os.remove(p)
    os.makedirs(folder, exist_ok=True)


def main(argv=None):
    p = argparse.ArgumentParser(prog="sweep", description=__doc__.splitlines()[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="\n".join(__doc__.splitlines()[2:]))
    p.add_argument("file", help="sweep YAML (a path, or the name of a file in modrob_sweep/sweeps/)")
    p.add_argument("--runs", type=int, default=None,
                   help="repetitions per parameter combination (overrides the file)")
    p.add_argument("--address", default=None, help="join this Ray cluster (host:port of `ray start --head`)")
    p.add_argument("--workers", type=int, default=None,
                   help="trials side by side on this machine (default: its cores / the trial's cpus); "
                   "ignored with --address")
    p.add_argument("--out", default=None, help="results folder (default out/sweeps/<name>/)")
    p.add_argument("--need", type=int, default=None, help="exit 1 when fewer trials succeed")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="change a fixed parameter of the file (repeatable), e.g. --set jitter=0.02")
    p.add_argument("--trials", default=None,
                   help="only these trials (numbers as in trials.csv, e.g. 3,7,12): re-run some of a sweep")
    args = p.parse_args(argv)
    if args.runs is not None and args.runs < 1:
        p.error("--runs must be at least 1, got %d" % args.runs)
    if args.workers is not None and args.workers < 1:
        p.error("--workers must be at least 1, got %d" % args.workers)
    try:
        path = find_file(args.file)
        sweep = load(path, runs=args.runs)
        for item in args.set:
            if "=" not in item:
                raise SweepError("--set takes NAME=VALUE, e.g. --set jitter=0.02; got %r" % item)
            sweep.set_fixed(*item.split("=", 1))
        if args.trials:
            sweep.select(args.trials)
        out = os.path.abspath(args.out or os.path.join(sweep.root, "out", "sweeps", sweep.name))
        prepare_out(out)
        from modrob_sweep.runner import run
        t0 = time.monotonic()
        workers = args.workers
        if workers is None and not args.address:
            workers = max(1, int((os.cpu_count() or 1) // sweep.cpus))
        rows, interrupted = run(sweep, out, address=args.address, workers=workers)
    except SweepError as exc:
        print("sweep: %s" % exc, file=sys.stderr)
        return 2
    wall = time.monotonic() - t0
    meta = {"sweep file": os.path.relpath(path, sweep.root) if path.startswith(sweep.root) else path,
            "scenario": "`%s`" % " ".join(sweep.command),
            "run": "%s, commit %s, %s" % (time.strftime("%Y-%m-%d %H:%M %Z"), commit(sweep.root),
                                          "Ray cluster at %s" % args.address if args.address
                                          else "this machine, %d worker(s)" % workers),
            "wall time": "%.0f s for %d trials (%.0f trials per hour)%s"
                         % (wall, len(rows), 3600.0 * len(rows) / wall if wall > 0 else 0,
                            "; INTERRUPTED after these" if interrupted else "")}
    if rows:
        written = results.write_all(rows, out, sweep.name, sweep.parameter_names, sweep.varying(),
                                    sweep.result["metrics"], meta)
        ok = sum(r["outcome"] == "success" for r in rows)
        names = ", ".join(os.path.relpath(w, out) for w in written)
        print("[sweep] %s: %s; wrote %s" % (sweep.name, results.rate_text(ok, len(rows)), names))
        per_hour = 3600.0 * len(rows) / wall if wall > 0 else 0
        print("[sweep] results in %s (%.0f s, %.0f trials per hour)" % (out, wall, per_hour))
    else:
        ok = 0
        print("[sweep] %s: no trial finished" % sweep.name)
    if interrupted:
        return 130
    if args.need is not None and ok < args.need:
        print("[sweep] %d trials succeeded, fewer than --need %d" % (ok, args.need), file=sys.stderr)
        return 1
    return 0

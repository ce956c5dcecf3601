"""``make demo SCENARIO=katana``: the can stack headless on its own ROS master.

Runs katana_stack.launch (real_time_factor 0, no GUI), prints the stack's progress lines
(``[katana] ...``) and its RESULT line as they come, keeps the launch's whole output in
``katana_demo.log``, and writes under --out: katana_scan_detections.png, katana_joint_tracking.png
and katana_result.yaml (the launch ends itself after the result). Exit status 0 only when the
result says success."""
import argparse
import os
import subprocess
import sys

import yaml

from modrob_sim import scenario_launch


def shown(line):
    """The launch's lines a person watching the demo sees."""
    return line.startswith("[katana]") or line.startswith("RESULT")


def main(argv=None):
    p = argparse.ArgumentParser(prog="katana_demo", description=__doc__.splitlines()[0])
    p.add_argument("--out", default=os.path.join(os.environ.get("MODROB_ROOT", "."), "out"))
    p.add_argument("--jitter", type=float, default=0.0, help="shift the cans by up to this much (m), seeded")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--scenario", default="katana", choices=["katana"], help="(from make demo)")
    a = p.parse_args(argv)
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    log_path = os.path.join(out, "katana_demo.log")
    result_path = os.path.join(out, "katana_result.yaml")
    if os.path.exists(result_path):
        os.remove(result_path)
    scenario_launch.sigterm_as_exit()
    launch = scenario_launch.start(["katana_sim", "katana_stack.launch", "gui:=false", "real_time_factor:=0",
                                    "out_dir:=%s" % out, "result_file:=%s" % result_path,
                                    "jitter:=%s" % a.jitter, "seed:=%s" % a.seed], subprocess.PIPE)
    print("[katana] starting the simulator, the arm and the stacker (%s; log: %s)"
          % (os.environ["ROS_MASTER_URI"], log_path), flush=True)
    try:
        with open(log_path, "w") as log:
            for raw in launch.stdout:
                line = raw.decode("utf-8", "replace")
                log.write(line)
                if shown(line):
                    sys.stdout.write(line)
                    sys.stdout.flush()
        launch.wait()
    finally:
        scenario_launch.stop(launch)
        launch.stdout.close()
    try:
        with open(result_path) as fh:
            result = yaml.safe_load(fh) or {}
    except (OSError, yaml.YAMLError) as exc:
        print("[katana] no result: %s (see %s)" % (exc, log_path), flush=True)
        return 1
    return 0 if result.get("success") is True else 1

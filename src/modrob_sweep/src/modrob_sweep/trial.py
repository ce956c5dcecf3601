"""One trial, isolated, on whichever machine runs it (no Ray here: the runner calls this in a task).

The trial gets its own folder (<sweep out>/trials/<trial>/: the scenario's --out / {out}, its
console log trial.log, ROS_LOG_DIR and ROS_HOME), its own ROS master port ({port} and
ROS_MASTER_URI; the demos start their own master on a free port), its seed, and with ``render`` its
own Xvfb display. It runs under the reaper (modrob_sweep.reaper), is stopped after ``timeout_s``
wall seconds and leaves no process behind.

Outcomes: success / failure (the result file says so, or the exit code when it has no success
field), crashed (ended without a result file), timeout (stopped after timeout_s), plus, from the
runner, infra_error and lost (the trial could not be run, twice).
"""
import json
import math
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

import yaml

from modrob_sweep import InfraError
from modrob_sweep.reaper import EX_TEMPFAIL
from modrob_sweep.spec import Trial, format_argv, format_result_path
from modrob_sim.scenario_launch import free_port

OUTCOMES = ("success", "failure", "crashed", "timeout", "infra_error", "lost", "error")


def field(data, dotted):
    """data['a']['b'] for 'a.b'; None when absent."""
    cur = data
    for part in str(dotted).split("."):
        if not isinstance(cur, dict) or part not in cur:
            return None
        cur = cur[part]
    return cur


def _number(v):
    if isinstance(v, bool):
        return float(v)
    if isinstance(v, (int, float)):
        return float(v)
    try:
        return float(v)
    except (TypeError, ValueError):
        return v


def read_result(path):
    """The result file as a mapping, or None when there is none; a file that is not YAML/JSON is
    read as None too (the trial then counts as crashed, with the reason in detail)."""
    if not path or not os.path.exists(path):
        return None, "no result file %s" % path if path else "no result file configured"
    try:
        with open(path) as fh:
            data = yaml.safe_load(fh)
    except (OSError, yaml.YAMLError) as exc:
        return None, "unreadable result file %s: %s" % (path, exc)
    if not isinstance(data, dict):
        return None, "result file %s is not a mapping" % path
    return data, ""


def run_trial(task, trial, out_root, token, attempt=1, grace_s=None):
    """Run ``trial`` (a Trial or its dict) of the sweep ``task`` (Sweep.as_task()); returns the
    table row (a dict). Raises InfraError when the trial could not be set up (retried by the runner)."""
    if isinstance(trial, dict):
        trial = Trial(trial["trial"], trial["params"], trial["seed"])
    out = os.path.join(out_root, "trials", "%04d" % trial.index)
    try:
        if os.path.isdir(out):
            shutil.rmtree(out)            # a retried trial starts clean
        os.makedirs(os.path.join(out, "ros_log"))
        os.makedirs(os.path.join(out, "ros_home"))
    except OSError as exc:
        raise InfraError("trial %d: cannot make its folder %s on %s: %s"
                         % (trial.index, out, socket.gethostname(), exc))
    port = free_port()
    argv = format_argv(task["command"], trial, out, port)
    result_path = format_result_path(task["result"]["file"], trial, out, port)
    env = dict(os.environ)
    env.update({"ROS_MASTER_URI": "http://localhost:%d" % port, "ROS_LOG_DIR": os.path.join(out, "ros_log"),
                "ROS_HOME": os.path.join(out, "ros_home"), "MODROB_SWEEP_SEED": str(trial.seed),
                "PYTHONUNBUFFERED": "1"})
    status_path = os.path.join(out, "reaper_status.json")
    cmd = [sys.executable, "-m", "modrob_sweep.reaper", "--token", "%s-%d" % (token, trial.index),
           "--parent", str(os.getpid()), "--status", status_path]
    cmd += ["--xvfb"] if task.get("render") else []
    cmd += ["--"] + argv
    with open(os.path.join(out, "command.txt"), "w") as fh:
        fh.write(" ".join(argv) + "\n")
    t0 = time.monotonic()
    timed_out = False
    with open(os.path.join(out, "trial.log"), "w") as log:
        try:
            proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT,
                                    stdin=subprocess.DEVNULL,
                                    cwd=out, start_new_session=True)
        except OSError as exc:
            raise InfraError("trial %d: cannot start the reaper on %s: %s" % (trial.index,
                                                                              socket.gethostname(), exc))
        try:
            proc.wait(timeout=task["timeout_s"])
        except subprocess.TimeoutExpired:
            timed_out = True
            proc.send_signal(signal.SIGTERM)     # the reaper stops the whole trial
            proc.wait()
        except BaseException:
            proc.send_signal(signal.SIGTERM)     # cancelled: the reaper stops the trial before we go
            proc.wait()
            raise
    wall = time.monotonic() - t0
    status = {}
    try:
        with open(status_path) as fh:
            status = json.load(fh)
    except (OSError, ValueError):
        status = {"infra": "the reaper left no status (exit %s)" % proc.returncode}
    if status.get("infra") or proc.returncode == EX_TEMPFAIL and not status.get("exit") == EX_TEMPFAIL:
        raise InfraError("trial %d on %s: %s" % (trial.index, socket.gethostname(), status.get("infra")))
    row = {"trial": trial.index, "host": socket.gethostname(), "outcome": None, "wall_s": round(wall, 3),
           "sim_s": math.nan}
    row.update(trial.params)
    row["seed"] = trial.seed
    res = task["result"]
    data, why = read_result(result_path) if not timed_out else (None, "")
    for m in res["metrics"]:
        row[m] = _number(field(data, m)) if data is not None else math.nan
        if row[m] is None:
            row[m] = math.nan
    if data is not None and field(data, res["sim_time"]) is not None:
        row["sim_s"] = _number(field(data, res["sim_time"]))
    ended = ("exit %s" % status["exit"]) if status.get("exit") is not None else (
        "killed by signal %s" % status.get("signal"))
    if timed_out:
        row["outcome"], detail = "timeout", "no end after %g s: stopped" % task["timeout_s"]
    elif data is None:
        row["outcome"], detail = "crashed", "%s; %s" % (ended, why)
    else:
        ok = field(data, res["success"])
        if ok is None:
            ok = status.get("exit") == 0
        row["outcome"] = "success" if bool(ok) else "failure"
        detail = ended
    if status.get("leftovers"):
        detail += "; left running (stopped): %s" % ", ".join(status["leftovers"][:3])
    row["attempts"] = attempt
    row["detail"] = detail
    row["out"] = out
    return row

"""``rosrun modrob_sim tune_pid``: tune one joint's effort_controllers/JointPositionController.

    tune_pid --order 59,3,55,63,64,4,66,4,67,5,56,5 --gripper --joint joint2 --at joint4=0.8 --out out/tune
    tune_pid --urdf modrob0.urdf --controllers modrob0_controllers.yaml --joint joint3 --method sine

Runs against the ODE physics core directly (no ROS, faster than real time). Methods:
  relay  relay feedback -> Ku, Tu -> the --rule table (default "robot"), then a sinusoid check;
  sine   the seed's method: start from the current gains and search p, d, i for the best sinusoid
         tracking (bounded by a relay experiment);
  both   relay, then the sine search from its result (default).
Writes <out>/<ns>_<joint>_gains.yaml (ros_control format), <out>/<ns>_<joint>_step.png (step
response before/after) and, with --table, merges the gains into a shared table (by default
src/modrob_sim/config/tuned_gains.yaml is NOT touched unless --table is given).
"""
import argparse
import os
import sys

import yaml

from modrob_sim.errors import ModrobError
from modrob_sim.tuning.autotune import auto_tune
from modrob_sim.tuning.loops import PhysicsLoop
from modrob_sim.tuning.report import controller_yaml, plot_step, update_gains_table
from modrob_sim.tuning.rules import RULES


def parse_at(text):
    out = {}
    for item in (text or "").split(","):
        item = item.strip()
        if not item:
            continue
        if "=" not in item:
            raise ModrobError("--at takes joint=value pairs separated by commas, not '%s'" % item)
        k, v = item.split("=", 1)
        try:
            out[k.strip()] = float(v)
        except ValueError:
            raise ModrobError("--at: '%s' is not a number (joint %s)" % (v, k))
    return out


def load_robot(args):
    """(urdf text, {joint: pid dict}, namespace, robot key)."""
    if args.order:
        from modrob_build.build import RobotSpec, build_robot_set
        order = [int(v) for v in args.order.replace(" ", "").split(",") if v]
        res = build_robot_set([RobotSpec(order, (0.0, 0.0, 0.0))], gripper=args.gripper,
                              grip_force=args.grip_force)
        urdf = res.files["modrob0.urdf"]
        ctrl = yaml.safe_load(res.files["modrob0_controllers.yaml"])
        key = ",".join(str(i) for i in order) + ("+gripper" if args.gripper else "")
    else:
        if not args.urdf:
            raise ModrobError("give --order or --urdf")
        with open(args.urdf) as fh:
            urdf = fh.read()
        ctrl = {}
        if args.controllers:
            with open(args.controllers) as fh:
                ctrl = yaml.safe_load(fh) or {}
        key = os.path.basename(args.urdf)
    ns = next(iter(ctrl), "modrob0") if ctrl else "modrob0"
    gains = {}
    for cfg in (ctrl.get(ns) or {}).values():
        if isinstance(cfg, dict) and "pid" in cfg and "joint" in cfg:
            gains[cfg["joint"]] = cfg["pid"]
    return urdf, gains, ns, key


def main(argv=None):
    p = argparse.ArgumentParser(prog="tune_pid", description="PID tuning of one joint (relay / sinusoid).")
    src = p.add_argument_group("robot")
    src.add_argument("--order", help="module order, e.g. 59,3,55,63,57,5 (built with modrob_build)")
    src.add_argument("--gripper", action="store_true")
    src.add_argument("--grip-force", type=float, default=3.0)
    src.add_argument("--urdf", help="a URDF file instead of --order")
    src.add_argument("--controllers",
                     help="its controller YAML (current gains, and gains holding the others)")
    p.add_argument("--joint", required=True)
    p.add_argument("--at", default="", help="configuration, e.g. joint2=0.3,joint4=0.8 (default all 0)")
    p.add_argument("--method", choices=("relay", "sine", "both"), default="both")
    p.add_argument("--rule", choices=sorted(RULES), default="robot")
    p.add_argument("--relay", type=float, default=None,
                   help="relay amplitude (default 20%% of the effort limit)")
    p.add_argument("--hysteresis", type=float, default=None)
    p.add_argument("--step", type=float, default=0.1, help="step size of the before/after test (rad or m)")
    p.add_argument("--out", default="out/tune_pid")
    p.add_argument("--table", default=None, help="merge the result into this gains table (YAML)")
    args = p.parse_args(argv)
    try:
        urdf, gains, ns, key = load_robot(args)
        at = parse_at(args.at)
        loop = PhysicsLoop(urdf, args.joint, start=at, hold_gains=gains)
        centre = at.get(args.joint, 0.0)
        initial = dict(gains.get(args.joint) or {"p": 100.0, "i": 0.0, "d": 10.0, "i_clamp": 0.0})
        print("tune_pid: %s joint %s at %.3f; current gains p %.4g i %.4g d %.4g"
              % (key, args.joint, centre, initial["p"], initial.get("i", 0), initial.get("d", 0)))
        sys.stdout.flush()
        res = auto_tune(loop, centre, initial, relay=args.relay, hysteresis=args.hysteresis, rule=args.rule,
                        refine=args.method != "relay", step=args.step,
                        log=lambda m: (print("  " + m), sys.stdout.flush()))
        if args.method == "sine":
            res.method = res.method.replace("relay+%s+" % args.rule, "relay-bounded ")
    except (ModrobError, OSError, yaml.YAMLError) as exc:
        print("tune_pid: %s" % exc, file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, "%s_%s" % (ns, args.joint))
    g = res.gains
    comment = ("tuned by tune_pid (%s) for %s at %s = %.3f\nstep %.3g: before %r\n               after %r"
               % (res.method, key, args.joint, centre, args.step, res.before, res.after))
    with open(stem + "_gains.yaml", "w") as fh:
        fh.write(controller_yaml(ns, args.joint, g, comment=comment))
    title = "%s %s: step %.3g before/after tuning (%s)" % (key, args.joint, args.step, res.method)
    plot_step(stem + "_step.png", title,
              [("before: p %.3g i %.3g d %.3g" % (initial["p"], initial.get("i", 0), initial.get("d", 0)),
                res.step_before),
               ("after: p %.3g i %.3g d %.3g" % (g["p"], g["i"], g["d"]), res.step_after)])
    better = res.after.iae < res.before.iae or res.sine_after.rms_error < res.sine_before.rms_error
    if args.table and not better:
        print("tune_pid: the tuned gains are not better than the current ones (step IAE %.4g vs %.4g, "
              "sine RMS %.3g vs %.3g rad): %s left unchanged"
              % (res.after.iae, res.before.iae, res.sine_after.rms_error, res.sine_before.rms_error,
                 args.table))
    elif args.table:
        update_gains_table(args.table, key, args.joint, g,
                           {"method": res.method, "at": {k: float(v) for k, v in at.items()},
                            "ku": float("%.5g" % res.relay.ku), "tu": float("%.5g" % res.relay.tu),
                            "overshoot": float("%.3g" % res.after.overshoot),
                            "settling_time": float("%.3g" % res.after.settling_time),
                            "sine_rms": float("%.3g" % res.sine_after.rms_error)})
    print("tune_pid: %s p %.4g i %.4g d %.4g i_clamp %.4g"
          % (args.joint, g["p"], g["i"], g["d"], g["i_clamp"]))
    print("  before: %r; %r" % (res.before, res.sine_before))
    print("  after:  %r; %r" % (res.after, res.sine_after))
    print("  wrote %s_gains.yaml and %s_step.png" % (stem, stem))
    return 0

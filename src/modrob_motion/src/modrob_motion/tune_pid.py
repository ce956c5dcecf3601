"""``rosrun modrob_motion tune_pid``: tune the effort_controllers/JointPositionController gains of one
joint, or of every arm joint of a robot (``--all``), and make them a robot's default gains.

    tune_pid --order 59,3,55,63,64,4,66,4,67,5,56,5 --gripper --joint joint2 --at joint4=0.8 --out out/tune
    tune_pid --order 59,3,55,63,57,5 --gripper --all --at joint2=0.6 --defaults
    tune_pid --urdf modrob0.urdf --controllers modrob0_controllers.yaml --joint joint3 --method sine

Runs against the ODE physics core directly (no ROS, faster than real time). Methods:
  relay  relay feedback -> Ku, Tu -> the --rule table (default "robot"), then a sinusoid check;
  sine   the seed's method: start from the current gains and search p, d, i for the best sinusoid
         tracking (bounded by a relay experiment);
  both   relay, then the sine search from its result (default).
With --all every arm joint is tuned in turn (modrob_sim.tuning.robot), and a joint's new gains are
kept only if 0.1 rad steps settle with little overshoot in two more configurations too.
Writes <out>/<ns>_<joint>_gains.yaml (ros_control format), <out>/<ns>_<joint>_step.png (step
response before/after) and, with --table FILE or --defaults (modrob_build's config/tuned_gains.yaml,
where create_urdf_and_gazebo takes a robot's default gains from), merges the gains into that table.
"""
import argparse
import os
import sys

import yaml

from modrob_build.build import RobotSpec, build_robot_set
from modrob_build.tuned_gains import default_table_path
from modrob_msgs.errors import ModrobError
from modrob_sim.tuning import TuningError
from modrob_sim.tuning.autotune import auto_tune
from modrob_sim.tuning.loops import PhysicsLoop
from modrob_sim.tuning.report import controller_yaml, plot_step, round_gains
from modrob_sim.tuning.robot import tune_robot
from modrob_sim.tuning.rules import RULES


def update_gains_table(path, robot_key, joint, gains, info):
    """Merge one joint's tuned gains into the shared table ``path`` (YAML):
    robots: {<order>: {<joint>: {p, i, d, i_clamp, antiwindup, method, ...}}}."""
    table = {}
    if os.path.exists(path):
        with open(path) as fh:
            try:
                table = yaml.safe_load(fh) or {}
            except yaml.YAMLError as exc:
                raise TuningError("%s is not valid YAML (%s): fix or remove it" % (path, exc))
    robots = table.setdefault("robots", {})
    entry = round_gains(gains)
    entry.update(info)
    robots.setdefault(robot_key, {})[joint] = entry
    header = ("# PID gains tuned by `rosrun modrob_motion tune_pid` (relay feedback + Ziegler-Nichols\n"
              "# tables, then the seed's sinusoid check), per module order and joint, in ros_control's\n"
              "# pid keys.\n"
              "# create_urdf_and_gazebo (modrob_build) takes a robot's default gains from here. Regenerate\n"
              "# with `rosrun modrob_motion tune_pid --order ... --all --defaults`; do not edit by hand.\n")
    with open(path, "w") as fh:
        fh.write(header + yaml.safe_dump(table, default_flow_style=False, sort_keys=True))
    return table


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
        order = [int(v) for v in args.order.replace(" ", "").split(",") if v]
        res = build_robot_set([RobotSpec(order, (0.0, 0.0, 0.0))], gripper=args.gripper,
                              grip_force=args.grip_force, gains=args.start_from)
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


def arm_joints(gains):
    """The joints --all tunes: every controlled joint but the gripper's fingers (whose gains follow
    from the grip force), in the controllers' order."""
    return [j for j in gains if "finger" not in j]


def main(argv=None):
    p = argparse.ArgumentParser(prog="tune_pid", description="PID tuning of one joint (relay / sinusoid).")
    src = p.add_argument_group("robot")
    src.add_argument("--order", help="module order, e.g. 59,3,55,63,57,5 (built with modrob_build)")
    src.add_argument("--gripper", action="store_true")
    src.add_argument("--grip-force", type=float, default=3.0)
    src.add_argument("--urdf", help="a URDF file instead of --order")
    src.add_argument("--controllers",
                     help="its controller YAML (current gains, and gains holding the others)")
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--joint", help="the joint to tune")
    which.add_argument("--all", action="store_true", help="tune every arm joint in turn (not the fingers)")
    src.add_argument("--start-from", choices=("computed", "tuned"), default="computed",
                     help="with --order: the gains to start from and compare with (default: computed from "
                     "the inertias, so that a table is reproducible)")
    p.add_argument("--at", default="", help="configuration, e.g. joint2=0.3,joint4=0.8 (default all 0)")
    p.add_argument("--method", choices=("relay", "sine", "both"), default="both")
    p.add_argument("--rule", choices=sorted(RULES), default="robot")
    p.add_argument("--relay", type=float, default=None,
                   help="relay amplitude (default 20%% of the effort limit)")
    p.add_argument("--hysteresis", type=float, default=None)
    p.add_argument("--step", type=float, default=0.1, help="step size of the before/after test (rad or m)")
    p.add_argument("--out", default="out/tune_pid")
    tab = p.add_mutually_exclusive_group()
    tab.add_argument("--table", default=None, help="merge the result into this gains table (YAML)")
    tab.add_argument("--defaults", action="store_true",
                     help="merge the result into modrob_build's table (config/tuned_gains.yaml): the "
                     "default gains of robots built with this module order")
    p.add_argument("--max-bandwidth", type=float, default=4.0,
                   help="--all: slow each tuned loop to this closed-loop bandwidth in Hz (0.35 / rise time), "
                   "keeping its shape; 0 = as fast as the relay allows (follows set-point jitter)")
    p.add_argument("--max-overshoot", type=float, default=0.15,
                   help="--all: largest overshoot of a 0.1 rad step accepted in the check configurations")
    args = p.parse_args(argv)
    if args.defaults:
        args.table = default_table_path()
    if args.all:
        return main_all(args)
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


def _check_figures(new, before):
    """A check's figures for the table (step: overshoot, settling time; sinusoid: amplitude ratio,
    saturated share): the tuned gains' and, under 'before', the ones they replace."""
    def figures(m):
        if hasattr(m, "amplitude_ratio"):
            return {"amplitude_ratio": float("%.3g" % m.amplitude_ratio),
                    "saturation": float("%.3g" % m.saturation)}
        return {"overshoot": float("%.3g" % m.overshoot), "settling_time": float("%.3g" % m.settling_time)}
    out = figures(new)
    if before is not None:
        out["before"] = figures(before)
    return out


def main_all(args):
    """--all: tune every arm joint (modrob_sim.tuning.robot), write the YAML, plots and table."""

    def log(msg):
        print("  " + msg)
        sys.stdout.flush()
    try:
        urdf, gains, ns, key = load_robot(args)
        at = parse_at(args.at)
        joints = arm_joints(gains)
        if not joints:
            raise ModrobError("no arm joint with a PID controller to tune (give --controllers with the URDF)")
        print("tune_pid: %s, every arm joint (%s) at %s" % (key, ", ".join(joints), args.at or "zeros"))
        sys.stdout.flush()
        tuned, outcomes = tune_robot(urdf, gains, joints, at=at, rule=args.rule,
                                     refine=args.method != "relay", step=args.step,
                                     max_overshoot=args.max_overshoot, max_bandwidth=args.max_bandwidth,
                                     log=log)
    except (ModrobError, OSError, yaml.YAMLError) as exc:
        print("tune_pid: %s" % exc, file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)
    kept = [o for o in outcomes if o.accepted]
    with open(os.path.join(args.out, "%s_gains.yaml" % ns), "w") as fh:
        data = {ns: {"%s_position_controller" % j: {
            "type": "effort_controllers/JointPositionController", "joint": j, "pid": round_gains(tuned[j])}
            for j in joints}}
        fh.write("# tuned by tune_pid --all for %s at %s (%d of %d joints re-tuned)\n"
                 % (key, args.at or "zeros", len(kept), len(joints)))
        fh.write(yaml.safe_dump(data, default_flow_style=False, sort_keys=False))
    print("tune_pid: %s" % key)
    for o in outcomes:
        g = tuned[o.joint]
        r = o.result
        figs = ("step overshoot %.0f%% -> %.0f%%, settling %.2f -> %.2f s, sine RMS %.2g -> %.2g rad"
                % (100 * r.before.overshoot, 100 * r.after.overshoot, r.before.settling_time,
                   r.after.settling_time, r.sine_before.rms_error, r.sine_after.rms_error)) if r else ""
        print("  %-8s p %-8.4g i %-9.4g d %-8.4g %s; %s"
              % (o.joint, g["p"], g.get("i", 0), g.get("d", 0), o.reason, figs))
        if r is not None:
            stem = os.path.join(args.out, "%s_%s" % (ns, o.joint))
            plot_step(stem + "_step.png", "%s %s: step %.3g before/after tuning (%s, %s)"
                      % (key, o.joint, args.step, r.method, "kept" if o.accepted else "rejected"),
                      [("before: p %.3g i %.3g d %.3g" % (gains[o.joint]["p"], gains[o.joint].get("i", 0),
                                                          gains[o.joint].get("d", 0)), r.step_before),
                       ("after: p %.3g i %.3g d %.3g" % (r.gains["p"], r.gains["i"], r.gains["d"]),
                        r.step_after)])
        if args.table and o.accepted:
            update_gains_table(args.table, key, o.joint, tuned[o.joint], {
                "method": r.method, "at": {k: float(v) for k, v in at.items()},
                "ku": float("%.5g" % r.relay.ku), "tu": float("%.5g" % r.relay.tu),
                "overshoot": float("%.3g" % r.after.overshoot),
                "settling_time": float("%.3g" % r.after.settling_time),
                "sine_rms": float("%.3g" % r.sine_after.rms_error),
                "checked": {label: _check_figures(m, before) for label, m, before in o.checks}})
    print("  wrote %s" % os.path.join(args.out, "%s_gains.yaml" % ns))
    if args.table:
        print("  %d joint(s) merged into %s" % (len(kept), args.table))
    return 0

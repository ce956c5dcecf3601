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
--search ray: instead, Ray Tune draws --samples gain sets per joint from a search space around the
current gains (--space p=lo:hi,d=lo:hi,i=lo:hi, per joint joint2.p=lo:hi) and scores each with the
same step + sinusoid cost, stopping bad ones after the step (ASHA); on a local Ray or --address
(modrob_sweep.tune_search, docs/sweeps.md). Writes <out>/<ns>_gains.yaml and the step plots.
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
    srch = p.add_argument_group("search with Ray Tune")
    srch.add_argument("--search", choices=("ray",), default=None,
                      help="search the gains with Ray Tune instead of relay + sinusoid tuning")
    srch.add_argument("--samples", type=int, default=24, help="gain sets tried per joint")
    srch.add_argument("--space", default="", help="p=lo:hi,d=lo:hi,i=lo:hi (joint.p=lo:hi for one joint); "
                      "default x0.25 .. x4 around the current gains")
    srch.add_argument("--seed", type=int, default=0, help="seed of the random draws")
    srch.add_argument("--address", default=None,
                      help="a Ray cluster (host:port); default a Ray on this machine")
    srch.add_argument("--workers", type=int, default=None,
                      help="trials at once on this machine (default: cores)")
    which.add_argument("--evaluate", metavar="p=..,i=..,d=..",
                       help="score these gains of --eval-joint (the search's cost, step and sinusoid "
                       "figures) into <out>/pid_result.yaml: one trial of a gains sweep (pid_search.yaml)")
    p.add_argument("--eval-joint", default="joint2", help="--evaluate: the joint (default joint2)")
    args = p.parse_args(argv)
    if args.defaults:
        args.table = default_table_path()
    if args.evaluate:
        return main_evaluate(args)
    if args.search:
        return main_search(args)
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


def _gains_text(g):
    return "p %.3g i %.3g d %.3g" % (g["p"], g.get("i", 0), g.get("d", 0))


def main_evaluate(args):
    """--evaluate: the cost and figures of given gains (and of the current ones) as a result file."""
    from modrob_sim.tuning.sine import cost
    try:
        urdf, gains, ns, key = load_robot(args)
        at = parse_at(args.at)
        joint = args.eval_joint
        current = dict(gains.get(joint) or {"p": 100.0, "i": 0.0, "d": 10.0, "i_clamp": 0.0})
        asked = parse_at(args.evaluate)
        unknown = sorted(set(asked) - {"p", "i", "d", "i_clamp"})
        if unknown:
            raise ModrobError("--evaluate takes p, i, d, i_clamp; not %s" % ", ".join(unknown))
        given = dict(current, **asked)
        loop = PhysicsLoop(urdf, joint, start=at, hold_gains=gains)
        centre = at.get(joint, 0.0)
        c_now = cost(loop, current, centre, 0.1, 0.5, args.step)[0]
        c, s, sm = cost(loop, given, centre, 0.1, 0.5, args.step)
    except (ModrobError, OSError, yaml.YAMLError) as exc:
        print("tune_pid: %s" % exc, file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)
    res = {"success": bool(c < c_now), "cost": float(c), "current_cost": float(c_now), "joint": joint,
           "p": float(given["p"]), "i": float(given.get("i", 0)), "d": float(given.get("d", 0)),
           "overshoot": float(sm.overshoot), "settling_time": float(sm.settling_time), "iae": float(sm.iae),
           "sine_rms": float(s.rms_error), "saturation": float(s.saturation)}
    with open(os.path.join(args.out, "pid_result.yaml"), "w") as fh:
        yaml.safe_dump(res, fh, sort_keys=True)
    print("RESULT tune_pid --evaluate %s %s: cost %.4g (current gains %.4g), overshoot %.0f%%, sine RMS %.3g "
          "rad" % (joint, _gains_text(given), c, c_now, 100 * sm.overshoot, s.rms_error))
    return 0


def main_search(args):
    """--search ray: Ray Tune over each joint's gains (modrob_sweep.tune_search); YAML, plots, table."""
    from modrob_sim.tuning.autotune import measure
    from modrob_sweep import tune_search
    from modrob_sweep.runner import connect, interrupt_on_sigterm, shutdown

    def log(msg):
        print("  " + msg)
        sys.stdout.flush()
    token = "tune_pid-%d" % os.getpid()     # marks the Ray processes of this search (runner.shutdown)
    interrupt_on_sigterm()                  # SIGTERM, like Ctrl-C, stops Ray and removes its directory
    try:
        urdf, gains, ns, key = load_robot(args)
        at = parse_at(args.at)
        joints = arm_joints(gains) if args.all else [args.joint]
        if not joints:
            raise ModrobError("no arm joint with a PID controller to tune (give --controllers with the URDF)")
        spaces = tune_search.parse_space(args.space)
        unknown = sorted(j for j in spaces if j is not None and j not in joints)
        if unknown:
            raise ModrobError("--space names %s, not among the joints searched (%s)"
                              % (", ".join(unknown), ", ".join(joints)))
        if args.samples < 2:
            raise ModrobError("--samples must be at least 2 (the current gains and one more), got %d"
                              % args.samples)
        cpus = connect(args.address, args.workers, 1.0, token)
        print("tune_pid: %s, Ray Tune over %s at %s, %d gain sets per joint, %g CPUs"
              % (key, ", ".join(joints), args.at or "zeros", args.samples, cpus))
        sys.stdout.flush()
        found = {}
        for j in joints:
            current = dict(gains.get(j) or {"p": 100.0, "i": 0.0, "d": 10.0, "i_clamp": 0.0})
            override = dict(spaces.get(None, {}), **spaces.get(j, {}))
            space = tune_search.default_space(current, override)
            i_text = ", i %.4g..%.4g" % space["i"] if "i" in space else ""
            log("%s: p %.4g..%.4g, d %.4g..%.4g%s" % (j, space["p"][0], space["p"][1], space["d"][0],
                                                      space["d"][1], i_text))
            found[j] = (current, tune_search.search_joint(urdf, j, at, gains, current, space, args.samples,
                                                          args.seed, os.path.join(os.path.abspath(args.out),
                                                                                  "ray_tune"), log))
    except (ModrobError, OSError, yaml.YAMLError) as exc:
        print("tune_pid: %s" % exc, file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("tune_pid: interrupted; nothing written", file=sys.stderr)
        return 130
    finally:
        shutdown(token)     # and its temporary directory
    os.makedirs(args.out, exist_ok=True)
    tuned = {j: dict(gains.get(j) or {}) for j in (arm_joints(gains) if args.all else [args.joint])}
    for j, (current, res) in found.items():
        better = res["cost"] < res["current_cost"]
        if better:
            tuned[j] = res["gains"]
        loop = PhysicsLoop(urdf, j, start=at, hold_gains=gains)
        centre = at.get(j, 0.0)
        tb, mb, sb = measure(loop, current, centre, args.step)
        ta, ma, sa = measure(loop, res["gains"], centre, args.step)
        stem = os.path.join(args.out, "%s_%s" % (ns, j))
        plot_step(stem + "_step.png", "%s %s: step %.3g, current vs Ray Tune's best (%s)"
                  % (key, j, args.step, "kept" if better else "not better: kept the current"),
                  [("current: " + _gains_text(current), tb), ("searched: " + _gains_text(res["gains"]), ta)])
        print("  %-8s cost %.4g -> %.4g (%d tried, %d stopped early): p %.4g i %.4g d %.4g %s; step "
              "overshoot "
              "%.0f%% -> %.0f%%, settling %.2f -> %.2f s, sine RMS %.2g -> %.2g rad"
              % (j, res["current_cost"], res["cost"], res["trials"], res["stopped_early"], res["gains"]["p"],
                 res["gains"]["i"], res["gains"]["d"], "kept" if better else "(current kept)",
                 100 * mb.overshoot,
                 100 * ma.overshoot, mb.settling_time, ma.settling_time, sb.rms_error, sa.rms_error))
        if args.table and better:
            update_gains_table(args.table, key, j, res["gains"], {
                "method": "ray tune (%d samples, seed %d)" % (args.samples, args.seed),
                "at": {k: float(v) for k, v in at.items()}, "cost": float("%.4g" % res["cost"]),
                "overshoot": float("%.3g" % ma.overshoot), "settling_time": float("%.3g" % ma.settling_time),
                "sine_rms": float("%.3g" % sa.rms_error)})
    path = os.path.join(args.out, "%s_gains.yaml" % ns)
    with open(path, "w") as fh:
        data = {ns: {"%s_position_controller" % j: {
            "type": "effort_controllers/JointPositionController", "joint": j, "pid": round_gains(tuned[j])}
            for j in tuned}}
        fh.write("# tuned by tune_pid --search ray for %s at %s\n" % (key, args.at or "zeros"))
        fh.write(yaml.safe_dump(data, default_flow_style=False, sort_keys=False))
    print("  wrote %s" % path)
    if args.table:
        print("  merged the improved joints into %s" % args.table)
    return 0

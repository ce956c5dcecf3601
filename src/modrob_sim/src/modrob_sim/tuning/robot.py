"""Tune every arm joint of a robot, one after the other, and accept a joint's new gains only if they
hold up in other configurations too.

    gains, outcomes = tune_robot(urdf, current_gains, ["joint1", "joint2"], at={"joint2": 0.6})

Joint k is tuned at ``at`` (auto_tune: relay -> rule -> sinusoid search) while the others are held
by the best gains so far (the joints before it already by their tuned gains). That finds the fastest
loop the 1 ms control period allows; it is then slowed to ``max_bandwidth`` keeping its shape
(slow_down), given enough d that a saturating step (LARGE_STEP) from ``at`` overshoots as little, then
stepped at every configuration of ``configs`` (default: ``at``, all joints at 0, and a seeded random
one), next to the current gains: they are kept if every step settles and overshoots at most
``max_overshoot`` (or no more than the current gains do), else the current gains stay and the
outcome says why. A tuned loop is only as good as the configuration it was tuned in: the check is
what makes the table usable as a robot's default gains.
"""
import copy
import math

from modrob_sim.errors import ModrobError
from modrob_sim.tuning import TuningError
from modrob_sim.tuning.autotune import auto_tune, measure
from modrob_sim.tuning.experiments import run_pid, step_setpoint
from modrob_sim.tuning.loops import PhysicsLoop
from modrob_sim.tuning.metrics import step_metrics
from modrob_sim.tuning.sine import sine_response, tune_by_sine

MAX_OVERSHOOT = 0.15
STEP_DURATION = 2.0
T_STEP = 0.2
LARGE_STEP = 1.0          # rad: saturates every drive of the modular arms (a motion_terminal jump)
D_RAISE = 1.5             # factor on d per round while the large step overshoots
D_ROUNDS = 6
FAST_SINE_FREQ = 1.5      # Hz: a shake of the arm (the grasp sanity test) ...
FAST_SINE_SPEED = 0.75    # ... peaking at this share of the joint's velocity limit (at most 0.25 rad)
MIN_SINE_RATIO = 0.8      # amplitude ratio the tuned loop must reach there (or the current one's)
COMMAND_RATE = 100.0      # Hz: set-points as motion_publisher streams them (held in between)
MAX_BANDWIDTH = 4.0       # Hz: the closed loop's 0.35 / rise time, see slow_down


class JointOutcome(object):
    """What happened to one joint: the tuning result, the check rows and whether it was kept."""

    def __init__(self, joint, result, checks, accepted, reason):
        self.joint = joint
        self.result = result          # TuneResult, or None if tuning failed
        self.checks = checks          # [(config label, StepMetrics new, StepMetrics current)]
        self.accepted = accepted
        self.reason = reason


def _clip(q, lower, upper, margin=0.05):
    if lower is not None and upper is not None and upper > lower:
        return min(max(q, lower + margin), upper - margin)
    return q


def default_configs(urdf, joints, at, seed=1):
    """[(label, {joint: q})]: the tuning configuration, all joints at 0 and a seeded random one
    (each joint uniform in the middle 60 % of its range, +-1.5 rad if unlimited). Not the tuning
    pose mirrored: negating every angle of a serial arm mirrors it, which changes nothing the
    loops see."""
    import random
    loop = PhysicsLoop(urdf, joints[0], start=at)
    limits = {n: (j.lower, j.upper) for n, (j, _) in loop.holds.items()}
    limits[joints[0]] = (loop.lower, loop.upper)
    names = sorted(limits)
    rng = random.Random(seed)
    shaken = {}
    for n in names:
        lo, hi = limits[n]
        if lo is None or hi is None or hi <= lo:
            lo, hi = -1.5, 1.5
        mid, half = 0.5 * (lo + hi), 0.3 * (hi - lo)
        shaken[n] = round(rng.uniform(mid - half, mid + half), 3)
    zeros = {n: _clip(0.0, *limits[n]) for n in names}
    configs = [("tuning pose", dict(at)), ("zeros", zeros), ("random", shaken)]
    out, seen = [], []
    for label, cfg in configs:
        key = tuple(round(cfg.get(n, 0.0), 4) for n in names)
        if key not in seen:
            seen.append(key)
            out.append((label, cfg))
    return out


def step_check(urdf, joint, gains, config, step=0.1):
    """StepMetrics of ``joint`` stepping by ``step`` (towards the middle of its range) from
    ``config`` with ``gains`` {joint: pid}, the other joints held by theirs. Raises TuningError if
    the simulation blows up."""
    loop = PhysicsLoop(urdf, joint, start=config, hold_gains=gains)
    q0 = float(config.get(joint, 0.0))
    if loop.lower is not None and loop.upper is not None and q0 > 0.5 * (loop.lower + loop.upper):
        step = -abs(step)
    else:
        step = abs(step)
    trace = run_pid(loop, gains[joint], step_setpoint(q0, q0 + step, T_STEP), STEP_DURATION, q0)
    return step_metrics(trace, T_STEP, q0, q0 + step)


def fast_sine(loop):
    """(amplitude, frequency) of the fast-swing check: FAST_SINE_FREQ, peaking at FAST_SINE_SPEED of
    the joint's velocity limit (2 rad/s if none), at most 0.25 rad."""
    vlim = getattr(loop.joint, "velocity_limit", None) or 2.0
    return min(0.25, FAST_SINE_SPEED * vlim / (2 * math.pi * FAST_SINE_FREQ)), FAST_SINE_FREQ


def large_step(urdf, joint, config):
    """The saturating step used in the checks: LARGE_STEP, at most 40 % of the joint's range."""
    loop = PhysicsLoop(urdf, joint, start=config)
    if loop.lower is not None and loop.upper is not None and loop.upper > loop.lower:
        return min(LARGE_STEP, 0.4 * (loop.upper - loop.lower))
    return LARGE_STEP


def damp_for_large_steps(urdf, joint, gains, config, limit, log=None):
    """Raise the tuned joint's d (x1.5 per round) until a saturating step overshoots at most
    ``limit``: a loop tuned on small steps brakes too late once its drive saturates (p/d sets where
    braking starts). Returns (gains, StepMetrics of the large step, rounds)."""
    step = large_step(urdf, joint, config)
    g = {k: dict(v) for k, v in gains.items()}
    m = step_check(urdf, joint, g, config, step)
    rounds = 0
    while _settles(m) and m.overshoot > limit and rounds < D_ROUNDS:
        g[joint]["d"] *= D_RAISE
        rounds += 1
        m = step_check(urdf, joint, g, config, step)
        if log:
            log("  large step %.2g: d -> %.4g, overshoot %.0f %%" % (step, g[joint]["d"], 100 * m.overshoot))
    return g, m, rounds


def _remeasure(loop, res, gains, centre, step, how="damped"):
    """Update a TuneResult's 'after' figures (small step, sinusoid) for changed gains."""
    res.gains = dict(gains)
    res.step_after, res.after, res.sine_after = measure(loop, gains, centre, step)
    res.method += "+" + how


def slow_down(gains, factor):
    """The same loop shape ``factor`` times slower: for J q'' = u with u = p e + i int(e) + d e',
    scaling time by 1/factor keeps the damping and the response's shape when p, d, i go by
    factor^2, factor, factor^3 (i_clamp unchanged)."""
    g = dict(gains)
    g["p"] = gains["p"] * factor ** 2
    g["d"] = gains["d"] * factor
    g["i"] = gains.get("i", 0.0) * factor ** 3
    return g


def _slow_to(loop, res, fastest, bandwidth, centre, step, log):
    factor = bandwidth / fastest
    log("  %.1f Hz -> %.1f Hz: p, d, i x %.3g, %.3g, %.3g"
        % (fastest, bandwidth, factor ** 2, factor, factor ** 3))
    slow = slow_down(res.gains, factor)
    # the plant is not a pure inertia (gravity, damping, armature): re-shape at that speed, the
    # stiffness capped, damping and integral free, on the fast swing streamed at the command rate
    # (fast_sine; a d that brakes the whole velocity between set-points makes the loop lag)
    bounds = {"p": (0.5 * slow["p"], slow["p"]), "d": (0.1 * slow["d"], 4.0 * slow["d"]),
              "i": (0.05 * slow["i"], 4.0 * slow["i"])}
    amp, freq = fast_sine(loop)
    slow, _ = tune_by_sine(loop, slow, centre, amp, freq, rounds=2, bounds=bounds,
                           log=lambda m: log("  " + m), hold_rate=COMMAND_RATE)
    _remeasure(loop, res, slow, centre, step, "slowed to %.3g Hz" % bandwidth)


def _check_joint(urdf, joint, res, current, best, at, configs, step, loop, max_overshoot, log,
                 command_rate=COMMAND_RATE):
    """(candidate gains of the robot, check rows, problems) for the joint's gains in ``res``: d
    raised for a saturating step, then small steps in every configuration."""
    # the integral's clamp: the tuner sizes it from the holding effort in the tuning pose, but the
    # joint must hold the arm in every pose: keep the current clamp if it is larger (the computed
    # gains size it from the largest gravity torque)
    res.gains["i_clamp"] = max(res.gains.get("i_clamp", 0.0), float(current.get("i_clamp", 0.0)))
    candidate = dict(best)
    candidate[joint] = dict(res.gains)
    checks, problems = [], []
    try:
        big = large_step(urdf, joint, at)
        old_big = step_check(urdf, joint, best, at, big) if joint in best else None
        limit_big = max(max_overshoot,
                        old_big.overshoot if old_big is not None and _settles(old_big) else 0.0)
        candidate, new_big, rounds = damp_for_large_steps(urdf, joint, candidate, at, limit_big, log=log)
        if rounds:
            _remeasure(loop, res, candidate[joint], at.get(joint, 0.0), step)
        checks.append(("large step", new_big, old_big))
        log("  check %-12s new %r" % ("large step", new_big))
        if not _settles(new_big) or new_big.overshoot > limit_big + 1e-9:
            problems.append("large step: %r (limit %.0f %% overshoot)" % (new_big, 100 * limit_big))
    except (TuningError, ModrobError) as exc:
        problems.append("large step: %s" % exc)
    try:
        # a fast swing streamed as ROS nodes do (a set-point every 10 ms): ros_control's PID
        # differentiates the error, so between two set-points its d term brakes on the joint's whole
        # velocity and the kick at each new set-point is clipped at the effort limit: a loop with
        # much d lags (joint6 of the 6-DoF arm: 0.13 of 0.25 rad at 1.5 Hz, 0.26 with a set-point
        # every step)
        amp, freq = fast_sine(loop)
        centre = at.get(joint, 0.0)
        s_new = sine_response(loop, candidate[joint], centre, amp, freq, hold_rate=command_rate)
        s_old = sine_response(loop, current, centre, amp, freq, hold_rate=command_rate)
        need = min(MIN_SINE_RATIO, s_old.amplitude_ratio)
        checks.append(("fast sine", s_new, s_old))
        log("  check %-12s new %r" % ("fast sine", s_new))
        if s_new.amplitude_ratio < need:
            problems.append("fast sine: %.2g rad at %.1f Hz (set-points at %g Hz) followed with an amplitude "
                            "ratio %.2f (need %.2f)" % (amp, freq, command_rate, s_new.amplitude_ratio, need))
    except (TuningError, ModrobError) as exc:
        problems.append("fast sine: %s" % exc)
    for label, cfg in configs:
        try:
            new = step_check(urdf, joint, candidate, cfg, step)
            old = step_check(urdf, joint, best, cfg, step) if joint in best else None
        except (TuningError, ModrobError) as exc:
            problems.append("%s: %s" % (label, exc))
            continue
        checks.append((label, new, old))
        limit = max(max_overshoot, old.overshoot if old is not None and _settles(old) else 0.0)
        if not _settles(new):
            problems.append("%s: a %.2g step does not settle (%r)" % (label, step, new))
        elif new.overshoot > limit + 1e-9:
            problems.append("%s: overshoot %.0f %% (limit %.0f %%)"
                            % (label, 100 * new.overshoot, 100 * limit))
        log("  check %-12s new %r" % (label, new))
        if old is not None:
            log("  check %-12s old %r" % (label, old))
    return candidate, checks, problems


def _settles(m):
    return math.isfinite(m.settling_time) and math.isfinite(m.overshoot)


def tune_robot(urdf, gains, joints, at=None, rule="robot", refine=True, step=0.1, configs=None,
               max_overshoot=MAX_OVERSHOOT, max_bandwidth=MAX_BANDWIDTH, log=None):
    """Returns (gains {joint: pid} with the accepted tuned ones, [JointOutcome])."""
    log = log or (lambda _m: None)
    at = dict(at or {})
    best = {j: dict(g) for j, g in gains.items()}
    configs = configs or default_configs(urdf, joints, at)
    outcomes = []
    for joint in joints:
        log("%s: tuning at %s" % (joint, ", ".join("%s=%.3g" % kv for kv in sorted(at.items())) or "zeros"))
        current = dict(best.get(joint) or {"p": 100.0, "i": 0.0, "d": 10.0, "i_clamp": 0.0})
        try:
            loop = PhysicsLoop(urdf, joint, start=at, hold_gains=best)
            res = auto_tune(loop, at.get(joint, 0.0), current, rule=rule, refine=refine, step=step,
                            log=lambda m: log("  " + m))
        except ModrobError as exc:
            log("%s: tuning failed (%s); keeping the current gains" % (joint, exc))
            outcomes.append(JointOutcome(joint, None, [], False, "tuning failed: %s" % exc))
            continue
        # the relay and sinusoid find the fastest loop the 1 ms control period allows (5-15 Hz);
        # set-points come from nodes at 100 Hz, late now and then on a loaded machine, and such a
        # loop follows their jitter: slow it down to max_bandwidth, keeping its shape; if that loop
        # fails the checks, try 1.5 and 2.25 times faster, then the loop as tuned
        fastest = 0.35 / res.after.rise_time if res.after.rise_time > 0 else float("inf")
        ladder = [max_bandwidth * f for f in (1.0, 1.5, 2.25)] if max_bandwidth else []
        ladder = [bw for bw in ladder if bw < fastest] + [None]
        tried = []
        for bw in ladder:
            attempt = copy.copy(res)
            attempt.gains = dict(res.gains)
            if bw is not None:
                _slow_to(loop, attempt, fastest, bw, at.get(joint, 0.0), step, log)
            candidate, checks, problems = _check_joint(urdf, joint, attempt, current, best, at, configs,
                                                       step, loop, max_overshoot, log)
            improved = (attempt.after.iae < attempt.before.iae
                        or attempt.sine_after.rms_error < attempt.sine_before.rms_error)
            if not problems and not improved:
                problems = ["the tuned gains are not better (step IAE %.4g vs %.4g)"
                            % (attempt.after.iae, attempt.before.iae)]
            label = ("%.1f Hz" % bw) if bw is not None else ("as tuned (%.1f Hz)" % fastest)
            tried.append("%s: %s" % (label, "; ".join(problems) if problems else "passed"))
            if not problems:
                break
            log("  %s loop failed the checks: %s" % (label, "; ".join(problems)))
        res = attempt
        accepted = not problems
        reason = "accepted" if accepted else "kept the current gains: " + " | ".join(tried)
        if accepted:
            best = candidate
            if bw is None or bw > ladder[0]:
                reason = "accepted at %s" % tried[-1].split(":")[0]
        log("%s: %s (p %.4g i %.4g d %.4g)" % (joint, reason, res.gains["p"], res.gains["i"], res.gains["d"]))
        outcomes.append(JointOutcome(joint, res, checks, accepted, reason))
    return best, outcomes

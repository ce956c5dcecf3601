"""PID gains found by Ray Tune (``tune_pid --search ray``): for one joint, random gains drawn from a
search space (log-uniform p and d, uniform i), each scored by tuning's own cost
(modrob_sim.tuning.sine.cost_stages: step overshoot, IAE and steady-state error, then the seed's
sinusoid tracking) on the ODE physics core, on a local Ray or a cluster. ASHA stops a trial after
the step stage when its cost is already among the worse half, so the sinusoid is only run for
promising gains. The current gains are the first point evaluated: the result is never worse."""
import math
import os

from modrob_sweep import SweepError

STAGES = 2


def default_space(gains, override=None):
    """{key: (lo, hi)} around the current gains: p and d over x0.25 .. x4 (log-uniform); i over
    0 .. 4 x its value when it has one (else not searched). ``override`` {key: (lo, hi)} wins."""
    p = float(gains.get("p", 100.0)) or 100.0
    d = float(gains.get("d", 0.0)) or 0.01 * p
    space = {"p": (p / 4.0, 4.0 * p), "d": (d / 4.0, 4.0 * d)}
    i = float(gains.get("i", 0.0))
    if i > 0:
        space["i"] = (0.0, 4.0 * i)
    for k, (lo, hi) in (override or {}).items():
        if k not in ("p", "i", "d") or not (0 <= lo < hi) or (k != "i" and lo <= 0):
            raise SweepError("search space %s=%g:%g: give p, i or d with 0 <= lo < hi (p and d above 0: they "
                             "are drawn log-uniformly)" % (k, lo, hi))
        space[k] = (float(lo), float(hi))
    return space


def parse_space(text):
    """'p=10:2000,d=0.1:50' or per joint 'joint2.p=10:2000' -> {joint or None: {key: (lo, hi)}}."""
    out = {}
    for item in (text or "").split(","):
        item = item.strip()
        if not item:
            continue
        try:
            name, rng = item.split("=", 1)
            lo, hi = (float(v) for v in rng.split(":"))
        except ValueError:
            raise SweepError("--space takes key=lo:hi items separated by commas (key p, i or d, optionally "
                             "joint.key), e.g. p=50:800,d=1:20; got %r" % item)
        joint, _, key = name.strip().rpartition(".")
        out.setdefault(joint or None, {})[key] = (lo, hi)
    return out


def search_joint(urdf, joint, at, hold_gains, current, space, samples=24, seed=0, storage=None, log=None,
                 amplitude=0.1, freq=0.5, step=0.1):
    """Ray Tune over ``space`` for ``joint`` (Ray must be initialised). Returns a dict: gains (best,
    with the current i_clamp and antiwindup), cost, current_cost, trials, stopped_early."""
    from ray import tune
    from ray.tune.schedulers import ASHAScheduler
    from ray.tune.search.basic_variant import BasicVariantGenerator
    from modrob_msgs.errors import ModrobError
    from modrob_sim.tuning.loops import PhysicsLoop
    from modrob_sim.tuning.sine import cost_stages

    centre = float(at.get(joint, 0.0))
    fixed = {"i_clamp": float(current.get("i_clamp", 0.0)), "antiwindup": bool(current.get("antiwindup",
                                                                                           False))}
    if "i" not in space:
        fixed["i"] = float(current.get("i", 0.0))

    def trainable(config):
        gains = dict(fixed, **config)
        try:
            loop = PhysicsLoop(urdf, joint, start=at, hold_gains=hold_gains)
            for k, (c, _s, _sm) in enumerate(cost_stages(loop, gains, centre, amplitude, freq, step)):
                tune.report({"cost": c, "stage": k + 1})
        except (ModrobError, ValueError):        # gains that blow the model up: the worst cost
            tune.report({"cost": 1e9, "stage": STAGES})

    param_space = {}
    for k, (lo, hi) in space.items():
        param_space[k] = tune.uniform(lo, hi) if k == "i" else tune.loguniform(lo, hi)
    first = {k: float(current.get(k, 0.0)) for k in space}
    for k, (lo, hi) in space.items():
        first[k] = min(max(first[k], lo), hi)
    tuner = tune.Tuner(
        tune.with_resources(trainable, {"cpu": 1}),
        param_space=param_space,
        tune_config=tune.TuneConfig(
            num_samples=samples, metric="cost", mode="min",
            search_alg=BasicVariantGenerator(points_to_evaluate=[first], random_state=seed),
            scheduler=ASHAScheduler(time_attr="training_iteration", max_t=STAGES, grace_period=1,
                                    reduction_factor=2)),
        run_config=tune.RunConfig(name="tune_pid_%s" % joint,
                                  storage_path=os.path.abspath(storage or "out/ray_tune"),
                                  verbose=0))
    grid = tuner.fit()
    df = grid.get_dataframe()
    # a trial ASHA stopped after the step stage reports only part of the cost: compare finished ones
    done = df[df["stage"] == STAGES] if "stage" in df else df.iloc[0:0]
    if done.empty:
        raise SweepError("Ray Tune finished no trial for joint %s (errors: %s)"
                         % (joint, "; ".join(str(r.error) for r in grid if r.error)[:300] or "none"))
    best = done.loc[done["cost"].idxmin()]
    mine = done
    for k, v in first.items():
        mine = mine[(mine["config/%s" % k] - v).abs() <= 1e-9 * max(1.0, abs(v))]
    current_cost = float(mine["cost"].iloc[0]) if len(mine) else math.nan
    gains = dict(fixed, **{k: float(best["config/%s" % k]) for k in space})
    if log:
        log("%s: %d gain sets tried, %d stopped after the step stage; best cost %.4g (the current gains: "
            "%.4g)"
            % (joint, len(df), len(df) - len(done), best["cost"], current_cost))
    return {"gains": gains, "cost": float(best["cost"]), "current_cost": current_cost, "trials": len(df),
            "stopped_early": len(df) - len(done)}

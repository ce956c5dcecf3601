"""A sweep file (YAML) -> the trials to run. Pure: no Ray, no ROS.

    name: slide_friction              # results under out/sweeps/<name>/ (default: the file's stem)
    scenario:                         # exactly one of demo / launch / command
      demo: one_robot                 #   scripts/demo.sh <demo> --out {out} <args>   (make demo SCENARIO=)
      launch: [modrob_sweep, slide_trial.launch]   #   roslaunch -p {port} <pkg> <file> <args>
      command: [rosrun, modrob_motion, tune_pid]   #   any command
      args: ["mu:={mu}", "seed:={seed}", "result_file:={out}/result.yaml"]
    result:
      file: result.yaml               # the trial's result file (YAML or JSON), relative to {out}
      success: success                # its true/false field (default "success"; absent: the exit code)
      sim_time: sim_time              # its simulated-seconds field (the sim_s column)
      metrics: [distance, speed]      # fields copied into the table (a.b for nested fields)
    parameters:
      fixed:  {v0: 1.5}                            # the same in every trial
      grid:   {mu: [0.2, 0.4], h: {linspace: [0, 1, 5]}}   # every combination ...
      points: [{mu: 0.2, h: 0}, {mu: 0.4, h: 1}]   # ... or these combinations (not both)
      random: {jitter: {uniform: [-0.004, 0.004]}} # drawn per trial, seeded (uniform, normal,
                                                   # integers [lo, hi), choice [...])
    repetitions: 4                    # trials per combination (make sweep RUNS=N overrides)
    seed: 0                           # trial k gets seed + k as {seed}, unless `seed` is a parameter
    timeout_s: 300                    # wall seconds before a trial is stopped and recorded as timeout
    cpus: 1                           # CPUs one trial needs (Ray schedules by it)
    render: false                     # true: each trial gets its own Xvfb display

Placeholders in args: {out} (the trial's folder), {seed}, {trial}, {port} (the trial's ROS master
port) and every parameter's name.
"""
import itertools
import os
import string

import numpy as np
import yaml

from modrob_sweep import SweepError

BUILT_IN = ("out", "seed", "trial", "port")
DISTRIBUTIONS = ("uniform", "normal", "integers", "choice")
KEYS = ("name", "description", "scenario", "result", "parameters", "repetitions", "seed", "timeout_s", "cpus",
        "render")


class Trial(object):
    """One trial: its index, its parameter values (fixed, grid/point and random) and its seed."""

    def __init__(self, index, params, seed):
        self.index, self.params, self.seed = index, params, seed

    def as_dict(self):
        return {"trial": self.index, "params": dict(self.params), "seed": self.seed}

    def __repr__(self):
        return "Trial(%d, %r, seed=%d)" % (self.index, self.params, self.seed)


class Sweep(object):
    """A loaded sweep file. ``command`` is the argument template; ``trials`` the expanded list."""

    def __init__(self, data, source="<sweep>", runs=None, root=None):
        self.source = source
        if not isinstance(data, dict):
            raise SweepError("%s: a sweep file is a YAML mapping (name, scenario, result, parameters ...)"
                             % source)
        unknown = sorted(set(data) - set(KEYS))
        if unknown:
            raise SweepError("%s: unknown key(s) %s; a sweep knows %s" % (source, ", ".join(unknown),
                                                                          ", ".join(KEYS)))
        stem = os.path.splitext(os.path.basename(source))[0]
        self.name = str(data.get("name") or stem)
        if not self.name or "/" in self.name or self.name.startswith("."):
            raise SweepError("%s: name '%s' must be a plain folder name (results go to out/sweeps/<name>/)"
                             % (source, self.name))
        self.description = str(data.get("description") or "")
        self.root = root or os.environ.get("MODROB_ROOT") or os.getcwd()
        self.seed = _int(data.get("seed", 0), "seed", source)
        self.repetitions = _int(runs if runs is not None else data.get("repetitions", 1), "repetitions",
                                source, minimum=1)
        self.timeout_s = _number(data.get("timeout_s", 600), "timeout_s", source, positive=True)
        self.cpus = _number(data.get("cpus", 1), "cpus", source, positive=True)
        self.render = bool(data.get("render", False))
        self.command, self.kind = self._scenario(data.get("scenario"))
        self.result = self._result(data.get("result") or {})
        self.fixed, self.points, self.random = self._parameters(data.get("parameters") or {})
        self.parameter_names = list(self.fixed) + [n for n in (self.points[0] if self.points else {})
                                                   if n not in self.fixed] + sorted(self.random)
        self._check_placeholders()
        self.trials = self._expand()

    # --- scenario ------------------------------------------------------------------------------
    def _scenario(self, sc):
        src = self.source
        if not isinstance(sc, dict):
            raise SweepError("%s: 'scenario' must be a mapping with one of demo, launch, command (and args)"
                             % src)
        kinds = [k for k in ("demo", "launch", "command") if k in sc]
        extra = sorted(set(sc) - {"demo", "launch", "command", "args"})
        if len(kinds) != 1 or extra:
            raise SweepError("%s: 'scenario' takes exactly one of demo (a make demo SCENARIO), launch "
                             "([package, file.launch]) or command ([program, args...]), plus args; got %s"
                             % (src, ", ".join(sorted(sc)) or "nothing"))
        args = sc.get("args") or []
        if not isinstance(args, list):
            raise SweepError("%s: scenario.args must be a list of strings, e.g. [\"--seed\", \"{seed}\"]"
                             % src)
        args = [str(a) for a in args]
        kind = kinds[0]
        if kind == "demo":
            demo = os.path.join(self.root, "scripts", "demo.sh")
            return [demo, str(sc["demo"]), "--out", "{out}"] + args, "demo"
        value = sc[kind]
        if isinstance(value, str):
            value = value.split()
        if not isinstance(value, list) or not value:
            raise SweepError("%s: scenario.%s must be a list (or a string of words)" % (src, kind))
        value = [str(v) for v in value]
        if kind == "launch":
            if len(value) != 2 or not value[1].endswith(".launch"):
                raise SweepError("%s: scenario.launch is [package, file.launch], got %r" % (src, value))
            return ["roslaunch", "-p", "{port}"] + value + args, "launch"
        return value + args, "command"

    def _result(self, res):
        if not isinstance(res, dict):
            raise SweepError("%s: 'result' must be a mapping (file, success, sim_time, metrics)"
                             % self.source)
        extra = sorted(set(res) - {"file", "success", "sim_time", "metrics"})
        if extra:
            raise SweepError("%s: result knows file, success, sim_time, metrics; not %s"
                             % (self.source, ", ".join(extra)))
        metrics = res.get("metrics") or []
        if isinstance(metrics, str):
            metrics = [metrics]
        if not isinstance(metrics, list):
            raise SweepError("%s: result.metrics must be a list of field names" % self.source)
        return {"file": res.get("file"), "success": res.get("success", "success"),
                "sim_time": res.get("sim_time", "sim_time"), "metrics": [str(m) for m in metrics]}

    # --- parameters ----------------------------------------------------------------------------
    def _parameters(self, par):
        src = self.source
        if not isinstance(par, dict):
            raise SweepError("%s: 'parameters' must be a mapping of fixed, grid, points, random" % src)
        extra = sorted(set(par) - {"fixed", "grid", "points", "random"})
        if extra:
            raise SweepError("%s: parameters knows fixed, grid, points and random; not %s (put a parameter "
                             "under one of them)" % (src, ", ".join(extra)))
        fixed = dict(par.get("fixed") or {})
        grid, points = par.get("grid"), par.get("points")
        if grid and points:
            raise SweepError("%s: give parameters.grid or parameters.points, not both" % src)
        if grid:
            if not isinstance(grid, dict):
                raise SweepError("%s: parameters.grid maps a name to its values" % src)
            axes = [(name, _axis(name, values, src)) for name, values in grid.items()]
            points = [dict(zip([a[0] for a in axes],
                               combo)) for combo in itertools.product(*[a[1] for a in axes])]
        elif points:
            if not isinstance(points, list) or not all(isinstance(p, dict) for p in points):
                raise SweepError("%s: parameters.points is a list of mappings, e.g. [{mu: 0.2}, {mu: 0.4}]"
                                 % src)
            names = set(points[0])
            for k, p in enumerate(points):
                if set(p) != names:
                    raise SweepError("%s: parameters.points[%d] names %s, the first point %s: every point "
                                     "names "
                                     "the same parameters" % (src, k, sorted(p), sorted(names)))
        else:
            points = [{}]
        random = par.get("random") or {}
        if not isinstance(random, dict):
            raise SweepError("%s: parameters.random maps a name to a distribution" % src)
        for name, dist in random.items():
            _check_distribution(name, dist, src)
        seen = {}
        for group, names in (("fixed", fixed), ("grid/points", points[0]), ("random", random)):
            for n in names:
                if n in seen:
                    raise SweepError("%s: parameter '%s' is under both %s and %s" % (src, n, seen[n], group))
                if n in BUILT_IN and n != "seed":
                    raise SweepError("%s: '%s' is a built-in placeholder (%s), not a parameter name"
                                     % (src, n, ", ".join(BUILT_IN)))
                seen[n] = group
        return fixed, points, random

    def _check_placeholders(self):
        known = set(BUILT_IN) | set(self.parameter_names)
        fields = list(self.command) + [self.result["file"] or ""]
        for text in fields:
            for _, field, _, _ in string.Formatter().parse(text):
                if field is not None and field not in known:
                    raise SweepError("%s: '{%s}' in %r is neither a parameter nor one of %s"
                                     % (self.source, field, text, ", ".join(BUILT_IN)))

    def _expand(self):
        trials = []
        for rep in range(self.repetitions):
            for point in self.points:
                k = len(trials)
                params = dict(self.fixed)
                params.update(point)
                params.update(draw(self.random, self.seed, k))
                seed = int(params["seed"]) if "seed" in params else self.seed + k
                trials.append(Trial(k, params, seed))
        return trials

    def set_fixed(self, name, value):
        """Change a fixed parameter (``--set name=value``); the trials are expanded again. A value
        is read as YAML (0.02 is a number, true a bool, text stays text)."""
        if name not in self.fixed:
            raise SweepError("%s: --set %s: only fixed parameters can be set (%s has %s)"
                             % (self.source, name, self.name, ", ".join(self.fixed) or "none"))
        self.fixed[name] = yaml.safe_load(value) if isinstance(value, str) else value
        self.trials = self._expand()

    def select(self, text):
        """Keep only the trials numbered in ``text`` ("3,7,12"); their parameters and seeds stay."""
        try:
            wanted = [int(v) for v in str(text).split(",") if v.strip()]
        except ValueError:
            raise SweepError("--trials takes trial numbers separated by commas, e.g. 3,7,12; got %r" % text)
        missing = [k for k in wanted if not 0 <= k < len(self.trials)]
        if missing or not wanted:
            raise SweepError("%s has trials 0-%d; no trial %s" % (
                self.source, len(self.trials) - 1, ", ".join(map(str, missing)) or "given"))
        self.trials = [self.trials[k] for k in sorted(set(wanted))]

    def varying(self):
        """The parameters whose value differs between trials (the summary's and plots' axes)."""
        out = []
        for n in self.parameter_names:
            values = {repr(t.params.get(n)) for t in self.trials}
            if len(values) > 1:
                out.append(n)
        return out

    def argv(self, trial, out, port):
        """The trial's command line."""
        return format_argv(self.command, trial, out, port)

    def result_path(self, trial, out, port=0):
        """The trial's result file, or None when the sweep names none."""
        return format_result_path(self.result["file"], trial, out, port)

    def as_task(self):
        """What a trial task needs of the sweep (plain data for Ray)."""
        return {"name": self.name, "command": self.command, "result": self.result,
                "timeout_s": self.timeout_s,
                "render": self.render, "kind": self.kind}


def _values(trial, out, port):
    return dict(trial.params, out=out, seed=trial.seed, trial=trial.index, port=port)


def format_argv(command, trial, out, port):
    """The command template with the trial's placeholders filled in."""
    values = _values(trial, out, port)
    return [a.format(**values) for a in command]


def format_result_path(template, trial, out, port):
    """The trial's result file (relative paths are inside its folder), or None."""
    if not template:
        return None
    path = template.format(**_values(trial, out, port))
    return path if os.path.isabs(path) else os.path.join(out, path)


def draw(random, seed, index):
    """The random parameters of trial ``index``: its own generator from (sweep seed, index), so a
    trial's values do not depend on how many trials come before it or run beside it."""
    rng = np.random.default_rng([int(seed) & 0xFFFFFFFF, index])
    out = {}
    for name in sorted(random):
        (kind, args), = random[name].items()
        if kind == "uniform":
            out[name] = float(rng.uniform(args[0], args[1]))
        elif kind == "normal":
            out[name] = float(rng.normal(args[0], args[1]))
        elif kind == "integers":
            out[name] = int(rng.integers(args[0], args[1]))
        else:
            out[name] = args[int(rng.integers(0, len(args)))]
    return out


def load(path, runs=None, root=None):
    """Read a sweep file; SweepError with the file and the problem named."""
    try:
        with open(path) as fh:
            data = yaml.safe_load(fh)
    except OSError as exc:
        raise SweepError("cannot read the sweep file %s: %s" % (path, exc.strerror or exc))
    except yaml.YAMLError as exc:
        raise SweepError("%s is not valid YAML: %s" % (path, exc))
    return Sweep(data, source=path, runs=runs, root=root)


def _axis(name, values, src):
    if isinstance(values, dict) and set(values) == {"linspace"}:
        lo, hi, n = values["linspace"]
        return [float(v) for v in np.linspace(float(lo), float(hi), int(n))]
    if isinstance(values, list) and values:
        return values
    raise SweepError("%s: parameters.grid.%s must be a non-empty list of values or {linspace: [lo, hi, n]}"
                     % (src, name))


def _check_distribution(name, dist, src):
    ok = isinstance(dist, dict) and len(dist) == 1 and next(iter(dist)) in DISTRIBUTIONS
    if ok:
        (kind, args), = dist.items()
        ok = isinstance(args, list) and (len(args) >= 1 if kind == "choice" else len(args) == 2)
        if ok and kind != "choice":
            ok = all(isinstance(a, (int, float)) and not isinstance(a, bool) for a in args)
    if not ok:
        raise SweepError("%s: parameters.random.%s must be one of {uniform: [lo, hi]}, {normal: [mean, sd]}, "
                         "{integers: [lo, hi]} (hi excluded) or {choice: [a, b, ...]}; got %r" % (src, name,
                                                                                                  dist))


def _int(v, what, src, minimum=0):
    if isinstance(v, bool) or not isinstance(v, int) or v < minimum:
        raise SweepError("%s: %s must be an integer >= %d, got %r" % (src, what, minimum, v))
    return v


def _number(v, what, src, positive=False):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or (positive and not v > 0):
        raise SweepError("%s: %s must be a %snumber, got %r" % (src, what, "positive " if positive else "",
                                                                v))
    return float(v)

"""The seed's method (section IV-F): command a sinusoid, compare measured with commanded, and adjust
the gains until they align. ``sine_response`` measures; ``tune_by_sine`` does the adjusting as a
coordinate search over log(p), log(d) (and log(i) when present), minimising the RMS tracking error
with penalties on effort saturation, step overshoot, step IAE and steady-state error."""
import math

import numpy as np

from modrob_sim.errors import ModrobError

from modrob_sim.tuning.experiments import run_pid, sine_setpoint, step_setpoint
from modrob_sim.tuning.metrics import sine_fit, step_metrics


class SineResult(object):
    def __init__(self, rms_error, amplitude_ratio, phase_lag, saturation, trace):
        self.rms_error = rms_error            # rad, after the first period
        self.amplitude_ratio = amplitude_ratio
        self.phase_lag = phase_lag            # rad (positive = measured lags)
        self.saturation = saturation          # fraction of samples at the effort limit
        self.trace = trace

    def __repr__(self):
        return ("SineResult(rms %.4g rad, gain %.3f, lag %.1f deg, saturated %.0f %%)"
                % (self.rms_error, self.amplitude_ratio, math.degrees(self.phase_lag), 100 * self.saturation))


def sine_response(loop, gains, centre, amplitude=0.2, freq=0.5, periods=3, hold_rate=None):
    """hold_rate: set-points held for 1/hold_rate s (a node publishing at that rate) instead of one
    per control step."""
    duration = periods / freq
    setpoint = sine_setpoint(centre, amplitude, freq)
    if hold_rate:
        smooth = setpoint
        setpoint = lambda t: smooth(math.floor(t * hold_rate + 1e-9) / hold_rate)  # noqa: E731
    trace = run_pid(loop, gains, setpoint, duration, centre)
    m = trace.t >= 1.0 / freq
    t, r, q = trace.t[m], trace.setpoint[m], trace.position[m]
    rms = float(np.sqrt(np.mean((r - q) ** 2)))
    ar, pr, _ = sine_fit(t, r, freq)
    aq, pq, _ = sine_fit(t, q, freq)
    lag = (pr - pq + math.pi) % (2 * math.pi) - math.pi
    lim = loop.effort_limit
    sat = float(np.mean(np.abs(trace.effort) >= 0.999 * lim)) if lim else 0.0
    return SineResult(rms, aq / ar if ar > 0 else 0.0, lag, sat, trace)


def cost_stages(loop, gains, centre, amplitude, freq, step=0.1, hold_rate=None):
    """The cost of ``gains`` in two stages, so that a search can drop bad gains after the first:
    yields (cost so far, SineResult or None, StepMetrics) after the step response (2 s: overshoot,
    IAE and steady-state error terms), then the whole cost with the sinusoid's terms added."""
    tr = run_pid(loop, gains, step_setpoint(centre, centre + step, 0.2), 2.0, centre)
    sm = step_metrics(tr, 0.2, centre, centre + step)
    step_part = (2.0 * max(0.0, sm.overshoot - 0.05) + 0.2 * sm.iae / step
                 + 10.0 * sm.steady_state_error / step)
    yield (step_part if math.isfinite(step_part) else 1e9), None, sm
    s = sine_response(loop, gains, centre, amplitude, freq, hold_rate=hold_rate)
    c = s.rms_error / amplitude + 0.5 * s.saturation + step_part
    yield (c if math.isfinite(c) else 1e9), s, sm


def cost(loop, gains, centre, amplitude, freq, step=0.1, hold_rate=None):
    """Sine RMS error (normalised by the amplitude) + saturation + step overshoot, IAE and
    steady-state error penalties (the last stage of cost_stages)."""
    for c, s, sm in cost_stages(loop, gains, centre, amplitude, freq, step, hold_rate):
        pass
    return c, s, sm


def tune_by_sine(loop, gains, centre, amplitude=0.2, freq=0.5, rounds=3, log=None, bounds=None,
                 hold_rate=None):
    """Coordinate search from ``gains``: each key (p, d, then i if non-zero) is scaled by factors
    0.5 .. 2 (narrowing each round) while the cost falls, within ``bounds`` {key: (lo, hi)}
    (without bounds an effort-limited loop would only ever ask for more gain).
    Returns (best gains, best cost)."""
    bounds = bounds or {}
    best = dict(gains)
    best_c = cost(loop, best, centre, amplitude, freq, hold_rate=hold_rate)[0]
    keys = ["p", "d"] + (["i"] if best.get("i", 0.0) > 0 else [])
    for rnd in range(rounds):
        factors = [2.0 ** (-1.0 / (rnd + 1)), 2.0 ** (1.0 / (rnd + 1))]
        for key in keys:
            improved = True
            while improved:
                improved = False
                for fct in factors:
                    trial = dict(best)
                    trial[key] = best[key] * fct
                    lo, hi = bounds.get(key, (0.0, float("inf")))
                    if not (lo <= trial[key] <= hi):
                        continue
                    try:
                        c = cost(loop, trial, centre, amplitude, freq, hold_rate=hold_rate)[0]
                    except (ModrobError, ValueError) as exc:   # a blow-up with these gains: reject them
                        if log:
                            log("  %s x%.2f rejected: %s" % (key, fct, exc))
                        continue
                    if c < best_c * 0.995:
                        best, best_c, improved = trial, c, True
                        if log:
                            log("  round %d: %s -> %.4g (cost %.4g)" % (rnd + 1, key, trial[key], c))
                        break
    return best, best_c

"""Step-response and tracking figures from a recorded trace."""
import math

import numpy as np


class Trace(object):
    """Samples of one experiment: time, set-point, position, effort (numpy arrays)."""

    def __init__(self, t, setpoint, position, effort):
        self.t = np.asarray(t, dtype=float)
        self.setpoint = np.asarray(setpoint, dtype=float)
        self.position = np.asarray(position, dtype=float)
        self.effort = np.asarray(effort, dtype=float)

    def __len__(self):
        return len(self.t)


class StepMetrics(object):
    def __init__(self, rise_time, overshoot, settling_time, steady_state_error, iae):
        self.rise_time = rise_time                    # s, 10 % -> 90 % (inf if never)
        self.overshoot = overshoot                    # fraction of the step
        self.settling_time = settling_time            # s, last exit from the 2 % band (inf if never)
        self.steady_state_error = steady_state_error  # rad, mean over the last 10 %
        self.iae = iae                                # integral of |error| (rad s)

    def as_dict(self):
        return {"rise_time": self.rise_time, "overshoot": self.overshoot, "settling_time": self.settling_time,
                "steady_state_error": self.steady_state_error, "iae": self.iae}

    def __repr__(self):
        return ("StepMetrics(rise %.3f s, overshoot %.1f %%, settling %.3f s, sse %.2e, iae %.4f)"
                % (self.rise_time, 100 * self.overshoot, self.settling_time, self.steady_state_error,
                   self.iae))


def step_metrics(trace, t_step, start, target, band=0.02):
    """Figures of the response to a step from ``start`` to ``target`` at time ``t_step``."""
    m = trace.t >= t_step
    t = trace.t[m] - t_step
    q = trace.position[m]
    size = target - start
    if len(t) < 3 or abs(size) < 1e-12:
        return StepMetrics(math.inf, 0.0, math.inf, math.inf, math.inf)
    frac = (q - start) / size
    rise = math.inf
    i10 = np.argmax(frac >= 0.1) if np.any(frac >= 0.1) else None
    i90 = np.argmax(frac >= 0.9) if np.any(frac >= 0.9) else None
    if i10 is not None and i90 is not None:
        rise = float(t[i90] - t[i10])
    overshoot = max(0.0, float(np.max(frac) - 1.0))
    outside = np.abs(frac - 1.0) > band
    if not np.any(outside):
        settling = 0.0
    elif outside[-1]:
        settling = math.inf
    else:
        last = np.nonzero(outside)[0][-1]
        settling = float(t[min(last + 1, len(t) - 1)])
    tail = max(1, len(q) // 10)
    sse = float(np.mean(np.abs(target - q[-tail:])))
    dt = np.diff(t, prepend=t[0])
    iae = float(np.sum(np.abs(target - q) * dt))
    return StepMetrics(rise, overshoot, settling, sse, iae)


def sine_fit(t, y, freq):
    """Amplitude, phase (rad) and offset of the fundamental of y at ``freq`` (least squares)."""
    w = 2 * math.pi * freq
    a = np.column_stack([np.sin(w * t), np.cos(w * t), np.ones_like(t)])
    coef, *_ = np.linalg.lstsq(a, y, rcond=None)
    amp = math.hypot(coef[0], coef[1])
    phase = math.atan2(coef[1], coef[0])
    return amp, phase, coef[2]

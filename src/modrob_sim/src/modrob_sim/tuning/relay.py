"""Relay feedback (Astrom & Hagglund 1984): replace the controller by a relay with hysteresis,

    u = u0 + d   while the error e = r - q was last above +eps,
    u = u0 - d   while it was last below -eps,

which drives the joint into a limit cycle at (nearly) the frequency where the loop's phase is
-180 deg. From its amplitude a and period Tu the describing function gives the ultimate gain

    Ku = 4 d / (pi * sqrt(a^2 - eps^2)).

u0 is the effort that holds the joint against gravity at the set-point, measured first by a short
PD hold (so that the cycle is symmetric).
"""
import math

import numpy as np

from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.tuning import TuningError
from modrob_sim.tuning.metrics import Trace


class RelayResult(object):
    def __init__(self, ku, tu, amplitude, relay, hysteresis, bias, cycles, trace):
        self.ku, self.tu, self.amplitude = ku, tu, amplitude
        self.relay, self.hysteresis, self.bias = relay, hysteresis, bias
        self.cycles = cycles
        self.trace = trace

    def __repr__(self):
        return ("RelayResult(Ku %.4g, Tu %.4g s, a %.4g, d %.4g, eps %.3g, u0 %.4g, %d cycles)"
                % (self.ku, self.tu, self.amplitude, self.relay, self.hysteresis, self.bias, self.cycles))


def holding_effort(loop, setpoint, hold_gains, seconds=1.5):
    """Mean effort over the last third of a PID hold at ``setpoint`` (the gravity load there)."""
    c = abs(hold_gains.get("i_clamp", 0.0))
    pid = Pid(PidGains(hold_gains["p"], hold_gains.get("i", 0.0), hold_gains.get("d", 0.0), c, -c, True))
    loop.reset(setpoint)
    n = int(round(seconds / loop.dt))
    efforts = []
    q = setpoint
    lim = loop.effort_limit
    for k in range(n):
        u = pid.compute(setpoint - q, loop.dt)
        if lim:
            u = max(-lim, min(lim, u))
        _, q, _ = loop.step(u)
        if k >= 2 * n // 3:
            efforts.append(u)
    return float(np.mean(efforts)), q


def relay_test(loop, setpoint, relay, hysteresis, bias=0.0, duration=6.0, min_cycles=4):
    """Run the relay around ``setpoint``; returns RelayResult. TuningError when no steady cycle."""
    if relay <= 0:
        raise TuningError("relay amplitude must be positive, got %r" % relay)
    lim = loop.effort_limit
    if lim and abs(bias) + relay > lim:
        raise TuningError("relay %.3g + holding effort %.3g exceed the joint's effort limit %.3g: "
                          "choose a smaller --relay" % (relay, abs(bias), lim))
    loop.reset(setpoint)
    n = int(round(duration / loop.dt))
    t = np.empty(n)
    q = np.empty(n)
    u = np.empty(n)
    s = 1.0
    qk = setpoint - 1e-9
    tk = 0.0
    for k in range(n):
        e = setpoint - qk
        if e > hysteresis:
            s = 1.0
        elif e < -hysteresis:
            s = -1.0
        effort = bias + s * relay
        tk, qk, _ = loop.step(effort)
        t[k], q[k], u[k] = tk, qk, effort
        limited = loop.lower is not None and loop.upper is not None
        if limited and not (loop.lower - 0.01 < qk < loop.upper + 0.01):
            raise TuningError("the relay drove joint '%s' to its limit (q = %.3f): use a smaller --relay"
                              % (loop.joint_name, qk))
    trace = Trace(t, np.full(n, setpoint), q, u)
    # upward crossings of the set-point by the position
    d = q - setpoint
    ups = np.nonzero((d[:-1] < 0) & (d[1:] >= 0))[0]
    if len(ups) < min_cycles + 2:
        raise TuningError("no steady relay oscillation of joint '%s' in %.1f s (%d cycles): raise --relay "
                          "or the duration" % (loop.joint_name, duration, max(0, len(ups) - 1)))
    ups = ups[2:]                      # drop the start-up cycles
    periods = np.diff(t[ups])
    tu = float(np.mean(periods[-min_cycles:]))
    seg = slice(ups[-min_cycles - 1] if len(ups) > min_cycles else ups[0], ups[-1])
    a = 0.5 * float(np.max(q[seg]) - np.min(q[seg]))
    if a <= hysteresis:
        raise TuningError("relay oscillation amplitude %.3g is not above the hysteresis %.3g"
                          % (a, hysteresis))
    ku = 4.0 * relay / (math.pi * math.sqrt(a * a - hysteresis * hysteresis))
    return RelayResult(ku, tu, a, relay, hysteresis, bias, len(periods), trace)

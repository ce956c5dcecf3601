"""Closed-loop experiments on a loop (see loops.py) with ros_control's PID (control_toolbox semantics)."""
import math

import numpy as np

from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.tuning.metrics import Trace


def pid_gains(g):
    clamp = abs(float(g.get("i_clamp", 0.0)))
    return PidGains(g["p"], g.get("i", 0.0), g.get("d", 0.0), clamp, -clamp, bool(g.get("antiwindup", False)))


def run_pid(loop, gains, setpoint, duration, q0):
    """Closed loop: effort = PID(setpoint(t) - q). Returns a Trace."""
    pid = Pid(pid_gains(gains))
    loop.reset(q0)
    n = int(round(duration / loop.dt))
    t = np.empty(n)
    sp = np.empty(n)
    q = np.empty(n)
    u = np.empty(n)
    tk, qk = 0.0, q0
    lim = loop.effort_limit
    for k in range(n):
        target = setpoint(tk)
        effort = pid.compute(target - qk, loop.dt)
        if lim:
            effort = max(-lim, min(lim, effort))
        tk, qk, _ = loop.step(effort)
        t[k], sp[k], q[k], u[k] = tk, target, qk, effort
    return Trace(t, sp, q, u)


def step_setpoint(start, target, t_step):
    return lambda t: target if t >= t_step else start


def sine_setpoint(centre, amplitude, freq):
    return lambda t: centre + amplitude * math.sin(2 * math.pi * freq * t)

"""Ziegler-Nichols style tuning tables: (ultimate gain Ku, ultimate period Tu) -> ros_control gains.

ros_control's PID is  p e + i * integral(e) + d * de/dt, so with Kp, Ti, Td of the tables:
p = Kp, i = Kp / Ti, d = Kp * Td.
"""
from modrob_sim.tuning import TuningError

# rule: (Kp / Ku, Ti / Tu, Td / Tu); Ti None = no integral action
RULES = {
    "classic": (0.6, 0.5, 0.125),          # Ziegler-Nichols 1942: quarter-amplitude decay
    "pessen": (0.7, 0.4, 0.15),            # Pessen integral rule
    "some_overshoot": (0.33, 0.5, 0.33),
    "no_overshoot": (0.2, 0.5, 0.33),
    "robot": (0.2, 2.0, 0.33),         # no_overshoot with a 4x slower integral: integrating joints
    "pd": (0.8, None, 0.125),
    "p": (0.5, None, 0.0),
}


def gains_from_ultimate(ku, tu, rule="no_overshoot", effort_limit=None):
    """dict p, i, d, i_clamp for ros_control. i_clamp = the effort limit (or 0.2 p when unknown)."""
    if rule not in RULES:
        raise TuningError("unknown tuning rule '%s'; choose one of %s" % (rule, ", ".join(sorted(RULES))))
    if not (ku > 0 and tu > 0):
        raise TuningError("ultimate gain and period must be positive (Ku %r, Tu %r)" % (ku, tu))
    kp_f, ti_f, td_f = RULES[rule]
    kp = kp_f * ku
    i = 0.0 if ti_f is None else kp / (ti_f * tu)
    d = kp * td_f * tu
    clamp = effort_limit if effort_limit else 0.2 * kp
    return {"p": kp, "i": i, "d": d, "i_clamp": clamp}

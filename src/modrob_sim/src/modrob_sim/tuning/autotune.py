"""The whole automatic tuning of one joint: hold -> relay -> rule -> (optional) sine refinement,
with step responses before and after for the report."""
import math

from modrob_sim.tuning import TuningError
from modrob_sim.tuning.experiments import run_pid, step_setpoint
from modrob_sim.tuning.metrics import step_metrics
from modrob_sim.tuning.relay import holding_effort, relay_test
from modrob_sim.tuning.rules import gains_from_ultimate
from modrob_sim.tuning.sine import sine_response, tune_by_sine


class TuneResult(object):
    def __init__(self, gains, relay, before, after, step_before, step_after, sine_before, sine_after,
                 method):
        self.gains = gains
        self.relay = relay
        self.before, self.after = before, after            # StepMetrics
        self.step_before, self.step_after = step_before, step_after   # Traces
        self.sine_before, self.sine_after = sine_before, sine_after   # SineResult
        self.method = method


def measure(loop, gains, centre, step=0.1, sine_amplitude=0.1, sine_freq=0.5):
    """The figures a TuneResult reports for ``gains``: (step Trace, StepMetrics, SineResult) of a
    ``step`` at 0.2 s (2.5 s watched) and of the sinusoid."""
    trace = run_pid(loop, gains, step_setpoint(centre, centre + step, 0.2), 2.5, centre)
    return (trace, step_metrics(trace, 0.2, centre, centre + step),
            sine_response(loop, gains, centre, sine_amplitude, sine_freq))


def auto_tune(loop, centre, initial_gains, relay=None, hysteresis=None, rule="no_overshoot", refine=True,
              step=0.1, sine_amplitude=0.1, sine_freq=0.5, log=None):
    """Tune the joint of ``loop`` around position ``centre``.

    initial_gains: the gains in use (also hold the joint while the gravity load is measured);
    relay: relay amplitude (default 20 % of the effort limit, or 5 N m); hysteresis: default a
    thousandth of the step (0.1 mrad for 0.1 rad). Returns TuneResult.
    """
    log = log or (lambda _m: None)
    lim = loop.effort_limit or 0.0
    bias, _ = holding_effort(loop, centre, initial_gains)
    log("holding effort at %.3f: %.4g" % (centre, bias))
    if relay is None:
        room = (lim - abs(bias)) if lim else 5.0
        relay = 0.2 * lim if lim else 5.0
        relay = min(relay, 0.8 * room)
        if relay <= 0:
            raise TuningError("joint '%s' needs %.3g of its %.3g effort limit to hold itself: no room for a "
                              "relay test" % (loop.joint_name, abs(bias), lim))
    if hysteresis is None:
        hysteresis = max(1e-4, 0.001 * step)
    rr = relay_test(loop, centre, relay, hysteresis, bias)
    log("relay: %r" % rr)
    gains = gains_from_ultimate(rr.ku, rr.tu, rule, effort_limit=lim or None)
    gains["antiwindup"] = True
    if lim:
        gains["i_clamp"] = min(lim, max(abs(bias) * 1.5, 0.1 * lim))
    log("%s rule: p %.4g i %.4g d %.4g" % (rule, gains["p"], gains["i"], gains["d"]))
    method = "relay+%s" % rule
    if refine:
        # stay inside what the relay experiment says is stable: P below the classic ZN value,
        # Td between Tu/16 and Tu/2, Ti not shorter than Tu/2
        ku, tu = rr.ku, rr.tu
        bounds = {"p": (0.05 * ku, 0.6 * ku), "d": (0.05 * ku * tu / 16, 0.6 * ku * tu / 2),
                  "i": (0.0, 0.6 * ku / (0.5 * tu))}
        gains, c = tune_by_sine(loop, gains, centre, sine_amplitude, sine_freq, rounds=2, log=log,
                                bounds=bounds)
        method += "+sine"
    tb, mb, sb = measure(loop, initial_gains, centre, step, sine_amplitude, sine_freq)
    ta, ma, sa = measure(loop, gains, centre, step, sine_amplitude, sine_freq)
    if not all(math.isfinite(v) for v in (gains["p"], gains["i"], gains["d"])):
        raise TuningError("tuning produced non-finite gains %r" % gains)
    return TuneResult(gains, rr, mb, ma, tb, ta, sb, sa, method)

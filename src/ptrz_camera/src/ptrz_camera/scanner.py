"""The scanner of seed 002 (section 3.3, appendix B.5): each chosen joint goes back and forth
between 0 and pi in steps of 0.05 rad with a 0.05 s pause per step.

As the seed describes it, the step does not land on pi, so the joint overshoots it by less than
one step before turning back, and it turns again at 0. The seed's code keeps one ``upper`` for
all joints and, going down, compares ``pos < 0``, so it also went one step below 0; this
implementation follows the description (positions stay in [0, pi + step)) and counts whole
steps, so rounding cannot drift the ends."""
import math

STEP = 0.05
PAUSE = 0.05
LOWER = 0.0
UPPER = math.pi


class ScanAxis(object):
    """One joint's back-and-forth; :meth:`advance` returns the next commanded position."""

    def __init__(self, step=STEP, lower=LOWER, upper=UPPER, start=None):
        if not (step > 0 and math.isfinite(step)):
            raise ValueError("scanner step must be a positive number, got %r" % (step,))
        if not upper > lower:
            raise ValueError("scanner upper end %r must be above the lower end %r" % (upper, lower))
        self.step, self.lower, self.upper = step, lower, upper
        self.k = 0 if start is None else int(round((start - lower) / step))
        self.rising = True

    @property
    def position(self):
        return self.lower + self.k * self.step

    def advance(self):
        if self.rising and self.position >= self.upper:
            self.rising = False
        elif not self.rising and self.k <= 0:
            self.rising = True
        self.k += 1 if self.rising else -1
        return self.position

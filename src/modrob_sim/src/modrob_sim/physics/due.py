"""The one rule of due times (docs/physics.md, "One step"): a hook due at ``due`` runs at the first
step at whose time ``t`` (its start for a before-hook, its end for an after-hook)
``t + DUE_TOLERANCE >= due``, so that the float sum of the steps' lengths never makes an update
one step late. A native stretch ends ``DUE_MARGIN`` before a due time, more than the tolerance,
so that rounding never lets it run past the due step (a hook called a step early finds nothing
to do). A hook whose work is only for listeners looks for one again only every ``IDLE_LOOK``
while it has none (:class:`IdleLook`)."""
DUE_TOLERANCE = 1e-9
DUE_MARGIN = 2e-9


def is_due(t, due):
    """Whether a hook due at ``due`` is due at the step time ``t``."""
    return t + DUE_TOLERANCE >= due


def stops_at(t, due):
    """Whether the World stops for Python at the step starting at ``t`` for a before-hook due at
    ``due`` (its native stretch ends ``DUE_MARGIN`` before it): a hook that gathers several into
    one (ros_control's control loop, its controllers) runs there those for which it would stop, and
    leaves out the others as if the World had stepped natively through ``t``."""
    return due - DUE_MARGIN <= t


#: simulated seconds between two looks for a listener while a hook whose work is only for listeners
#: (a sensor's topic, a controller's per-update message) has none: meanwhile the hook is not due, so
#: the World steps natively through its update times, and its first message after a listener comes
#: is at most this much after the listener came (docs/sensors.md, docs/controllers.md)
IDLE_LOOK = 0.1


class IdleLook(object):
    """When a hook whose work is only for listeners looks for one again. The hook calls
    :meth:`look` whenever it runs; while nobody listened at the last look it is due only at
    ``until`` (``IDLE_LOOK`` after that look), else at its own due times."""

    def __init__(self):
        #: while nobody listened at the last look: the simulated time of the next look (else None)
        self.until = None

    def look(self, t, listened):
        """``listened`` (whether someone listens now, at simulated time ``t``), remembered."""
        self.until = None if listened else t + IDLE_LOOK
        return listened

    def reset(self):
        """Look at the hook's next run (its own due times until then)."""
        self.until = None

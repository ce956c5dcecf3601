"""The one rule of due times (docs/physics.md, "One step"): a hook due at ``due`` runs at the first
step at whose time ``t`` (its start for a before-hook, its end for an after-hook)
``t + DUE_TOLERANCE >= due``, so that the float sum of the steps' lengths never makes an update
one step late. A native stretch ends ``DUE_MARGIN`` before a due time, more than the tolerance,
so that rounding never lets it run past the due step (a hook called a step early finds nothing
to do)."""
DUE_TOLERANCE = 1e-9
DUE_MARGIN = 2e-9


def is_due(t, due):
    """Whether a hook due at ``due`` is due at the step time ``t``."""
    return t + DUE_TOLERANCE >= due

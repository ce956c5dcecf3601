"""modrob_sweep: sweeps and Monte-Carlo runs of any scenario on Ray (docs/sweeps.md).

* :mod:`.spec`     -- a sweep YAML file -> the list of trials (pure, no Ray, no ROS)
* :mod:`.trial`    -- one trial, isolated: own folder, ROS master port, logs, seed, Xvfb, timeout
* :mod:`.reaper`   -- the supervisor process of a trial: leaves nothing of it behind
* :mod:`.runner`   -- trials as Ray tasks, locally or on a cluster, with a progress line
* :mod:`.results`  -- the trial table (CSV, Parquet), summary.md and the plots
* :mod:`.tune_search` -- Ray Tune over PID gains (``tune_pid --search ray``)
"""
from modrob_msgs.errors import ModrobError


class SweepError(ModrobError):
    """A sweep that cannot be run as written (bad YAML, unknown scenario, no Ray ...)."""


class InfraError(ModrobError):
    """A trial that could not be run through no fault of its scenario (no Xvfb, no folder ...):
    retried once."""

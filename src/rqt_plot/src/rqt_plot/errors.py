"""Errors of the plot library (all derive from modrob_msgs.errors.ModrobError)."""
from modrob_msgs.errors import ModrobError


class PlotError(ModrobError):
    """A series name, a field path or an output file is unusable."""

"""Errors of the reconfigure GUI's library (all derive from modrob_msgs.errors.ModrobError)."""
from modrob_msgs.errors import ModrobError


class ReconfigureError(ModrobError):
    """A dynamic_reconfigure server, its description or a value typed by the user is unusable."""

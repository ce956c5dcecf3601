"""Exception types of katana_sim; all derive from the workspace root ``ModrobError``."""
from modrob_msgs.errors import ModrobError


class KatanaError(ModrobError):
    """Root of katana_sim's errors."""


class ConfigError(KatanaError):
    """A plugin element, parameter or file that cannot be used (the message names it)."""


class UnreachableError(KatanaError):
    """An IK target the arm cannot reach; the message says why (too far, too close, joint limit)."""


class DetectionError(KatanaError):
    """A laser scan that cannot be interpreted (wrong sizes, NaN angles ...)."""

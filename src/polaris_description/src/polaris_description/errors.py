"""Typed errors of polaris_description (all derive from modrob_msgs.errors.ModrobError)."""
from modrob_msgs.errors import ModrobError


class PolarisError(ModrobError):
    """Root of this package's errors."""


class CommandError(PolarisError):
    """A command that cannot be executed (NaN, infinite, unknown key)."""


class ConfigError(PolarisError):
    """A configuration (PID table entry, waypoint file, parameter) that is missing or malformed."""

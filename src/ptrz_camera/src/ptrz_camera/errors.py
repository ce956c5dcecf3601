"""Errors of the ptrz_camera library; nodes catch PtrzError at their boundary."""
from modrob_msgs.errors import ModrobError


class PtrzError(ModrobError):
    """Root of ptrz_camera's errors."""


class ConfigError(PtrzError):
    """A configuration file or parameter is missing or malformed (the message names it)."""


class ZoomRangeError(PtrzError):
    """A field of view outside the camera's physical range."""


class TerminalError(PtrzError):
    """The keyboard teleop needs a terminal."""

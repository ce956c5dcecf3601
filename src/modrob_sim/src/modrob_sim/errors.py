"""The exception types of modrob_sim. Every error the library raises derives from ModrobError,
so a node can catch library errors at its boundary and log them without catching bugs."""


class ModrobError(Exception):
    """Root of the errors raised by modrob_sim's libraries."""


class ModelError(ModrobError):
    """A robot or world description that cannot be simulated (malformed URDF/SDF, a missing
    mesh, a duplicate model name, an unknown joint ...). The message names the thing."""


class SimulationError(ModrobError):
    """A failure while stepping (a model that cannot be restored, an invalid state request)."""


class ControllerError(ModrobError):
    """A controller that cannot be loaded or run (unknown type, missing parameter ...)."""

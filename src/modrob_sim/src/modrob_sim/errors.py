"""The exception types of modrob_sim. Every error the library raises derives from ModrobError
(defined in modrob_msgs.errors for the whole workspace),
so a node can catch library errors at its boundary and log them without catching bugs."""


from modrob_msgs.errors import ModrobError  # noqa: F401  (the workspace-wide root, re-exported)


class ModelError(ModrobError):
    """A robot or world description that cannot be simulated (malformed URDF/SDF, a missing
    mesh, a duplicate model name, an unknown joint ...). The message names the thing."""


class SimulationError(ModrobError):
    """A failure while stepping (a model that cannot be restored, an invalid state request)."""


class ControllerError(ModrobError):
    """A controller that cannot be loaded or run (unknown type, missing parameter ...)."""


class PluginError(ModrobError):
    """A /gazebo plugin that cannot be loaded as configured (a missing or malformed <plugin>
    parameter, a sensor without its link ...). The message names the model, plugin and tag."""


class RequestError(ModrobError):
    """A request to the /gazebo node that cannot be served (unknown model, NaN pose ...); the text
    becomes the service's status_message."""


class InputError(ModrobError, ValueError):
    """A value the physics core or the node refuses (a pose, twist, effort, position, physics
    parameter or time step out of range, NaN, the wrong shape). The message names the thing, the
    value and the limit. Also a ValueError, so code written against plain Python conventions
    (``except ValueError``) keeps working."""


class LoopStoppedError(SimulationError):
    """The simulation loop has stopped (the node is shutting down): a request handed to it was
    not run. Plugins answer stop/unload requests arriving now as done (they stop with the node)."""

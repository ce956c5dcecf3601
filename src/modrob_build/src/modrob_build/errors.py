"""The exception types of modrob_build. They derive from modrob_msgs' ModrobError, the root of
every library error in the workspace, so a node can catch them at its boundary."""
from modrob_msgs.errors import ModrobError


class BuildError(ModrobError):
    """Something the build cannot turn into a robot description. The message names the thing."""


class DatabaseError(BuildError):
    """A malformed module database (Modules.csv): the message names file, line and column."""


class OrderError(BuildError):
    """An invalid module order: the message names the position (1-based) and the module ID."""


class LayoutError(BuildError):
    """Inconsistent robot set-up: base positions that do not match the orders, bad numbers."""

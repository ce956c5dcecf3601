"""The root of every error the modrob libraries raise.

It lives in modrob_msgs, the package every other one already depends on, so that libraries low
in the stack (modrob_build, modrob_viz) share the root without depending on the simulator.
Nodes catch ModrobError at their boundary and log what, where and what to do."""


class ModrobError(Exception):
    """Root of the errors raised by the modrob workspace's libraries."""

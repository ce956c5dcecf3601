"""Errors of the node-graph library (all derive from modrob_msgs.errors.ModrobError)."""
from modrob_msgs.errors import ModrobError


class GraphError(ModrobError):
    """The master cannot be asked, graphviz is missing, or an output cannot be written."""

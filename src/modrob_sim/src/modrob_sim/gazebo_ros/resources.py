"""Resolving the resource URIs of robot and world descriptions to files (pure apart from rospkg,
which needs no master): package://pkg/path, model://name/path (GAZEBO_MODEL_PATH, and each ROS
package's models/ folder), file:///abs/path and plain paths."""
import os

import rospkg

from modrob_sim.errors import ModelError


class ResourceResolver(object):
    """Callable: ``resolver(uri) -> absolute path``; ModelError naming the URI when unresolvable."""

    def __init__(self, rospack=None):
        self._rospack = rospack or rospkg.RosPack()
        self._cache = {}

    def __call__(self, uri):
        if uri in self._cache:
            return self._cache[uri]
        path = self._resolve(uri)
        self._cache[uri] = path
        return path

    def _resolve(self, uri):
        if uri.startswith("package://"):
            rest = uri[len("package://"):]
            pkg, _, rel = rest.partition("/")
            try:
                base = self._rospack.get_path(pkg)
            except rospkg.ResourceNotFound:
                raise ModelError("%s: ROS package '%s' not found (is the workspace sourced and built?)"
                                 % (uri, pkg))
            path = os.path.join(base, rel)
        elif uri.startswith("model://"):
            rel = uri[len("model://"):]
            dirs = [d for d in os.environ.get("GAZEBO_MODEL_PATH", "").split(os.pathsep) if d]
            for d in dirs:
                if os.path.exists(os.path.join(d, rel)):
                    return os.path.abspath(os.path.join(d, rel))
            raise ModelError("%s: not found in GAZEBO_MODEL_PATH (%s)" % (uri, ":".join(dirs) or "empty"))
        elif uri.startswith("file://"):
            path = uri[len("file://"):]
        else:
            path = uri
        path = os.path.abspath(os.path.expanduser(path))
        if not os.path.exists(path):
            raise ModelError("%s: file %s does not exist" % (uri, path))
        return path

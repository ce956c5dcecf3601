"""Resolving the resource URIs of robot and world descriptions to files, as Gazebo finds them (pure
apart from rospkg, which needs no master).

- ``package://pkg/path`` through rospkg;
- ``model://name/path`` on Gazebo's model path: GAZEBO_MODEL_PATH, the ``gazebo_model_path``
  folders that packages export, ~/.gazebo/models (``physics.meshes.model_dirs``, the one rule);
- ``file:///abs/path`` and absolute paths as they are; a relative ``file://`` or plain path (a
  world's ``file://media/...``, ``worlds/x.world``) in the current folder, else on Gazebo's
  resource path: modrob_sim's own folder, GAZEBO_RESOURCE_PATH, the ``gazebo_media_path``
  folders that packages export (:meth:`ResourceResolver.resource_dirs`).
"""
import os

import rospkg

from modrob_sim.errors import ModelError
from modrob_sim.physics.meshes import ResourceNotFound, find_model_uri, model_dirs

#: modrob_sim's own folder (its worlds/ are Gazebo's worlds/ here)
PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))


class ResourceResolver(object):
    """Callable: ``resolver(uri) -> absolute path``; ModelError naming the URI when unresolvable
    (ResourceNotFound, with the folders searched, for a model:// or relative path found nowhere).
    ``exports`` (package_exports.PackageExports or None) adds the packages' exported folders."""

    def __init__(self, rospack=None, exports=None):
        self._rospack = rospack or rospkg.RosPack()
        self._exports = exports
        self._cache = {}

    def model_dirs(self):
        return model_dirs(self._exports.model_paths if self._exports is not None else ())

    def resource_dirs(self):
        """Gazebo's resource path: modrob_sim's folder, GAZEBO_RESOURCE_PATH, exported media paths."""
        dirs = [PACKAGE_DIR] + [d for d in os.environ.get("GAZEBO_RESOURCE_PATH", "").split(os.pathsep) if d]
        if self._exports is not None:
            dirs += self._exports.media_paths
        out = []
        for d in dirs:
            if d not in out:
                out.append(d)
        return out

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
            return find_model_uri(uri, self.model_dirs())
        else:
            path = uri[len("file://"):] if uri.startswith("file://") else uri
            path = os.path.expanduser(path)
            if not os.path.isabs(path) and not os.path.exists(path):
                return self.find_resource(path, uri)
        path = os.path.abspath(path)
        if not os.path.exists(path):
            raise ModelError("%s: file %s does not exist" % (uri, path))
        return path

    def find_resource(self, rel, uri=None):
        """A relative path on Gazebo's resource path (``worlds/empty.world``, ``media/...``)."""
        dirs = self.resource_dirs()
        for d in dirs:
            path = os.path.join(d, rel)
            if os.path.exists(path):
                return os.path.abspath(path)
        what = uri or rel
        raise ResourceNotFound(what, [os.getcwd()] + dirs, "%s: not found (looked in the current folder %s "
                               "and on Gazebo's resource path: %s)" % (what, os.getcwd(), ", ".join(dirs)))

"""Finding and reading Gazebo world files (pure, no rospy).

``find_world(name, resolver)`` resolves what gazebo_ros's ``world_name`` argument accepts: an
absolute or relative path, ``worlds/<file>`` on Gazebo's resource path (modrob_sim's own worlds/
folder, GAZEBO_RESOURCE_PATH, the ``gazebo_media_path`` folders packages export: see
resources.ResourceResolver), ``package://pkg/path`` and ``file://``. ``world_physics(text)``
reads the ``<physics>`` and ``<gravity>`` of a ``<world>``.
"""
import os

from modrob_sim.errors import ModelError
from modrob_sim.physics.sdf_reader import read_world_settings


def find_world(name, resolver):
    """Absolute path of a world file; ModelError naming what was tried when it does not exist.
    ``resolver`` is a resources.ResourceResolver."""
    if not name:
        raise ModelError("world_name is empty: give a world file (for example worlds/empty.world)")
    try:
        path = resolver(name)
    except ModelError as exc:
        raise ModelError("world file %r not found (%s); give an absolute path, worlds/<file> from "
                         "modrob_sim, GAZEBO_RESOURCE_PATH or a package's exported gazebo_media_path, or "
                         "package://<pkg>/<path>" % (name, exc))
    if not os.path.isfile(path):
        raise ModelError("world file %r: %s is not a file" % (name, path))
    return path


def world_physics(text):
    """dict with the keys present among time_step, real_time_factor, real_time_update_rate and
    gravity of a world file (read by the physics core's one reader of a world's <physics>);
    ModelError if it is not XML or a value is bad."""
    settings = read_world_settings(text, "world file")
    return {k: v for k, v in settings.items()
            if k in ("time_step", "real_time_factor", "real_time_update_rate", "gravity")}

"""Finding and reading Gazebo world files (pure, no rospy).

``find_world(name, resolver)`` resolves what gazebo_ros's ``world_name`` argument accepts: an
absolute or relative path, ``worlds/<file>`` on Gazebo's resource path (modrob_sim's own worlds/
folder, GAZEBO_RESOURCE_PATH, the ``gazebo_media_path`` folders packages export: see
resources.ResourceResolver), ``package://pkg/path`` and ``file://``. ``world_physics(text)``
reads the ``<physics>`` and ``<gravity>`` of a ``<world>``.
"""
import os
import xml.etree.ElementTree as ET

from modrob_sim.errors import ModelError
from modrob_sim.physics.sdf_versions import upgrade


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
    gravity, from the first ``<physics>`` (and ``<gravity>``) of a world; ModelError if not XML."""
    try:
        root = upgrade(ET.fromstring(text), "world", lambda key, message: None)   # the reader says it
    except ET.ParseError as exc:
        raise ModelError("the world file is not valid XML: %s" % exc)
    world = root if root.tag == "world" else root.find("world")
    out = {}
    if world is None:
        return out
    physics = world.find("physics")
    grav = world.findtext("gravity")
    if physics is not None:
        for tag, key in (("max_step_size", "time_step"), ("real_time_factor", "real_time_factor"),
                         ("real_time_update_rate", "real_time_update_rate")):
            v = physics.findtext(tag)
            if v is not None and v.strip():
                try:
                    out[key] = float(v)
                except ValueError:
                    raise ModelError("<physics><%s> of the world is not a number: %r" % (tag, v))
        grav = grav or physics.findtext("gravity")
    if grav:
        vals = grav.split()
        if len(vals) != 3:
            raise ModelError("<gravity> of the world needs three numbers, got %r" % grav)
        out["gravity"] = tuple(float(v) for v in vals)
    return out

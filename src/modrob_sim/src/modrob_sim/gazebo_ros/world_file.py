"""Finding and reading Gazebo world files (pure, no rospy).

``find_world(name)`` resolves what gazebo_ros's ``world_name`` argument accepts: an absolute or
relative path, ``worlds/<file>`` (Gazebo's resource path: modrob_sim's own worlds/ folder and each
entry of GAZEBO_RESOURCE_PATH), ``package://pkg/path`` and ``file://``. ``world_physics(text)``
reads the ``<physics>`` and ``<gravity>`` of a ``<world>``.
"""
import os
import xml.etree.ElementTree as ET

from modrob_sim.errors import ModelError

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))


def resource_dirs():
    dirs = [PACKAGE_DIR]
    for entry in os.environ.get("GAZEBO_RESOURCE_PATH", "").split(os.pathsep):
        if entry:
            dirs.append(entry)
    return dirs


def find_world(name, resolve=None):
    """Absolute path of a world file; ModelError naming what was tried when it does not exist."""
    if not name:
        raise ModelError("world_name is empty: give a world file (for example worlds/empty.world)")
    tried = []
    if "://" in name:
        if resolve is None:
            raise ModelError("world_name %r is a URI but no resource resolver is available" % name)
        path = resolve(name)
        tried.append(path)
        if path and os.path.isfile(path):
            return os.path.abspath(path)
    else:
        candidates = [name] if os.path.isabs(name) else [os.path.abspath(name)] + [
            os.path.join(d, name) for d in resource_dirs()]
        for c in candidates:
            tried.append(c)
            if os.path.isfile(c):
                return os.path.abspath(c)
    raise ModelError("world file %r not found (tried: %s); give an absolute path, worlds/<file> from "
                     "modrob_sim or GAZEBO_RESOURCE_PATH, or package://<pkg>/<path>"
                     % (name, ", ".join(tried)))


def world_physics(text):
    """dict with the keys present among time_step, real_time_factor, real_time_update_rate and
    gravity, from the first ``<physics>`` (and ``<gravity>``) of a world; ModelError if not XML."""
    try:
        root = ET.fromstring(text)
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

"""Load ``libmodrob_raycast.so`` (built from ``modrob_raycast.c`` by the workspace build, CMake
target ``modrob_raycast`` of modrob_sim, found like the physics' native loop: see
:func:`modrob_sim.physics.native.find_library`) with ctypes.

:data:`LIB` is the loaded library or None; :data:`REASON` says why it is None (the ray sensors
then use the numpy caster, which knows boxes, spheres, cylinders, capsules and planes only).
"""
import ctypes
import logging

from modrob_sim.physics import native as physics_native

LOG = logging.getLogger("modrob_sim.sensors")
LIBRARY = "libmodrob_raycast.so"

LIB = None
REASON = None


def _declare(lib):
    vp, i, d = ctypes.c_void_p, ctypes.c_int, ctypes.c_double
    lib.rc_cast.restype = i
    lib.rc_cast.argtypes = [vp, i, vp, vp, vp, i, d, d, vp, vp]
    lib.rc_geom_aabb.restype = None
    lib.rc_geom_aabb.argtypes = [vp, vp]
    return lib


def load():
    global LIB, REASON
    if physics_native.LIB is None:
        REASON = "the physics' native loop is off (%s)" % (physics_native.REASON or "unavailable")
        return None
    try:
        LIB = _declare(ctypes.CDLL(physics_native.find_library(LIBRARY)))
    except (FileNotFoundError, OSError, AttributeError) as e:
        REASON = str(e)
        LOG.warning("native ray caster unavailable (%s): ray sensors use the numpy caster", e)
        LIB = None
    return LIB


load()

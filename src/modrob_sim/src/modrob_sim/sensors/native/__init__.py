"""Load ``libmodrob_raycast.so`` (built from ``modrob_raycast.c`` by the workspace build, CMake
target ``modrob_raycast`` of modrob_sim, found like the physics' native loop: see
:func:`modrob_sim.physics.native.find_library`) with ctypes.

:data:`LIB` is the loaded library or None; :data:`REASON` says why it is None (the ray sensors
then use the numpy caster, which knows boxes, spheres, cylinders, capsules and planes only). A
library built from another ``modrob_raycast.c`` than the one next to this module is not loaded
(:data:`STALE`, as the physics' loop): ray sensors then refuse to start, naming the files.
"""
import ctypes
import logging
import os

from modrob_sim.physics import native as physics_native

LOG = logging.getLogger("modrob_sim.sensors")
LIBRARY = "libmodrob_raycast.so"
SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "modrob_raycast.c")

LIB = None
REASON = None
STALE = False


def _declare(lib, held):
    """``lib``'s calls release the GIL (the rays: rc_run); ``held``'s keep it (the same library
    through ctypes.PyDLL: calls of microseconds in the simulation's thread)."""
    vp, i, d = ctypes.c_void_p, ctypes.c_int, ctypes.c_double
    lib.rc_run.restype = i
    lib.rc_run.argtypes = [vp, vp, vp]
    lib.rc_prepare = held.rc_prepare
    lib.rc_prepare.restype = vp
    lib.rc_prepare.argtypes = [vp, i, vp, vp, vp, i, d, d, vp, vp, i]
    lib.rc_needs_now = held.rc_needs_now
    lib.rc_needs_now.restype = i
    lib.rc_needs_now.argtypes = [vp]
    lib.rc_release = held.rc_release
    lib.rc_release.restype = None
    lib.rc_release.argtypes = [vp]
    lib.rc_ray_angles.restype = None
    lib.rc_ray_angles.argtypes = [vp, i, vp, vp]
    lib.rc_geom_aabb.restype = None
    lib.rc_geom_aabb.argtypes = [vp, vp]
    return lib


def load():
    global LIB, REASON, STALE
    LIB, REASON, STALE = None, None, False
    if physics_native.LIB is None:
        REASON = "the physics' native loop is off (%s)" % (physics_native.REASON or "unavailable")
        return None
    try:
        path = physics_native.find_library(LIBRARY)
        lib = ctypes.CDLL(path)
        stale = physics_native.source_mismatch(lib, path, SOURCE)
        if stale:
            REASON, STALE = stale, True
            return None
        LIB = _declare(lib, ctypes.PyDLL(path))
    except (FileNotFoundError, OSError, AttributeError) as e:
        REASON = str(e)
        LOG.warning("native ray caster unavailable (%s): ray sensors use the numpy caster", e)
        LIB = None
    return LIB


load()

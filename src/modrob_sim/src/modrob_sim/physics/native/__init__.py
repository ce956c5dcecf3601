"""Load the C hot loop ``libmodrob_ode_native.so`` (built from ``modrob_ode_native.c`` by the
workspace build: ``catkin_make`` or ``colcon build``, CMake target ``modrob_ode_native`` of
modrob_sim) with ctypes.

The library is looked up in ``$MODROB_NATIVE_LIB_DIR`` (if set), then ``<prefix>/lib`` and
``<prefix>/lib/modrob_sim`` of every prefix on ``CMAKE_PREFIX_PATH`` (the devel space or the
install space that ``setup.bash`` put there). Nothing is compiled at run time. When it is missing,
:data:`LIB` is None and :data:`REASON` says why and how to build it; the World then uses the
pure-Python path (same semantics, slower; triangle meshes collide as their bounding boxes), and
the /gazebo node says so in one line at start-up. ``MODROB_PHYSICS_NATIVE=0`` selects the
pure-Python path on purpose (:data:`DISABLED`).

A library built from another ``modrob_ode_native.c`` than the one next to this module (a pull or
rebase without a build: its compiled-in SHA-256, :func:`source_mismatch`) is not loaded:
:data:`STALE` is True, :data:`REASON` names the files and says to build, and a World that would
use the native loop refuses to start rather than run on the pure-Python path unnoticed.
"""
import ctypes
import hashlib
import os

from .. import odelib

LIBRARY = "libmodrob_ode_native.so"
SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "modrob_ode_native.c")
BUILD_HINT = ("build the workspace (catkin_make, or colcon build and source install/setup.bash), "
              "then start again")

LIB = None
#: the same library loaded through ctypes.PyDLL: its calls keep the GIL (for calls of microseconds
#: that the simulation thread makes between batches); its users declare the signatures they call
LIB_HELD = None
REASON = None
#: the native loop is off on purpose (MODROB_PHYSICS_NATIVE=0)
DISABLED = False
#: the library was built from another source than SOURCE: it must be built again
STALE = False


def library_dirs():
    """Where built libraries of modrob_sim are looked for, in order."""
    dirs = []
    override = os.environ.get("MODROB_NATIVE_LIB_DIR")
    if override:
        dirs.append(override)
    for prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep):
        if prefix:
            dirs.extend([os.path.join(prefix, "lib"), os.path.join(prefix, "lib", "modrob_sim")])
    return dirs


def find_library(name):
    """Path of the built library ``name`` (e.g. libmodrob_ode_native.so); FileNotFoundError
    naming the places looked at and how to build it when it is not there."""
    dirs = library_dirs()
    for d in dirs:
        path = os.path.join(d, name)
        if os.path.isfile(path):
            return path
    raise FileNotFoundError("%s is not built (looked in %s); %s"
                            % (name, ", ".join(dirs) or "CMAKE_PREFIX_PATH, which is empty", BUILD_HINT))


def source_mismatch(lib, path, source):
    """Why the library ``lib`` (loaded from ``path``) was not built from ``source``, or None when
    it was: the SHA-256 the build compiled in (``modrob_source_sha256()``) against the file's. None
    too when ``source`` is not there to compare (an install space without sources)."""
    if not os.path.isfile(source):
        return None
    with open(source, "rb") as f:
        want = hashlib.sha256(f.read()).hexdigest()
    try:
        fn = lib.modrob_source_sha256
    except AttributeError:
        built = None
    else:
        fn.restype = ctypes.c_char_p
        fn.argtypes = []
        built = fn().decode("ascii", "replace")
    if built == want:
        return None
    return ("%s is out of date: it was built from another %s than the one there now (%s: sha256 %s; "
            "the library: %s). Build again: `make build` in the workspace (or catkin_make / colcon "
            "build), then start again; MODROB_PHYSICS_NATIVE=0 runs the pure-Python physics on purpose"
            % (path, os.path.basename(source), source, want[:12],
               "built from %s" % built[:12] if built else "no checksum, built before they had one"))


def _declare(lib):
    vp, i, d, ul = ctypes.c_void_p, ctypes.c_int, ctypes.c_double, ctypes.c_ulong
    sig = {
        "mr_ctx_new": (vp, [vp, vp, vp]),
        "mr_ctx_free": (None, [vp]),
        "mr_set_geom": (None, [vp, vp, i, i, i, i, i]),
        "mr_remove_geom": (None, [vp, vp]),
        "mr_set_surface": (None, [vp, i, d, d, d, d, d, d, d, d, d, i]),
        "mr_clear_adjacency": (None, [vp]),
        "mr_add_adjacent": (None, [vp, i, i, i]),
        "mr_set_model_count": (None, [vp, i]),
        "mr_model_contacts": (i, [vp, i]),
        "mr_last_contacts": (i, [vp]),
        "mr_contact_log": (i, [vp, vp, vp, i]),
        "mr_contact_vals": (i, []),
        "mr_collide": (i, [vp, d, d, d, d, d, i]),
        "mr_quickstep": (ul, [vp, d, ul]),
        "mr_step": (i, [vp, d, d, d, d, d, i]),
        "mr_step_checked": (i, [vp, d, d, d, d, d, i, i, vp, i, d, d, ctypes.POINTER(ctypes.c_int)]),
        "mr_set_seed": (None, [vp, ul]),
        "mr_anchors_forget": (None, [vp]),
        "mr_get_seed": (ul, [vp]),
        "mr_max_model_contacts": (i, [vp, ctypes.POINTER(ctypes.c_int)]),
        "mr_check_bodies": (i, [vp, i, i, d, d]),
        "mr_apply_damping": (None, [vp, vp, vp, i]),
        "mr_mesh_create": (vp, [vp, vp, i, vp, i, i]),
        "mr_mesh_destroy": (None, [vp, vp]),
        "mr_geom_set_body": (None, [vp, vp]),
        "mr_geom_enable": (None, [vp, i]),
        "mr_geom_is_enabled": (i, [vp]),
        "mr_geom_set_offset": (None, [vp, d, d, d, d, d, d, d]),
        "mr_geom_set_pose": (None, [vp, d, d, d, d, d, d, d]),
        "mr_geom_set_bits": (None, [vp, ul, ul]),
        "mr_geom_aabb": (None, [vp, vp]),
        "mr_max_depth": (d, [vp, vp]),
        "mr_apply_actuators": (None, [vp, i, d, d, i, i]),
        "mr_actuator_tracking_error": (None, [vp, d, vp]),
        "mr_actuator_size": (ctypes.c_size_t, []),
        "mr_track_turns": (None, [vp, i]),
        "mr_apply_model_actuators": (None, [vp, i]),
        "mr_watch_new": (i, [vp]),
        "mr_watch_add_geom": (i, [vp, i, vp]),
        "mr_watch_drain": (i, [vp, i, vp, vp, i]),
        "mr_watch_free": (None, [vp, i]),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype = res
        f.argtypes = args
    return lib


def load():
    global LIB, LIB_HELD, REASON, DISABLED, STALE
    LIB, LIB_HELD, REASON, DISABLED, STALE = None, None, None, False, False
    if os.environ.get("MODROB_PHYSICS_NATIVE", "1").strip().lower() in ("0", "false", "no", "off"):
        REASON = "disabled by MODROB_PHYSICS_NATIVE=0"
        DISABLED = True
        return None
    if not odelib.AVAILABLE:
        REASON = "PyODE's object layout could not be verified"
        return None
    try:
        path = find_library(LIBRARY)
        lib = ctypes.CDLL(path)
        stale = source_mismatch(lib, path, SOURCE)
        if stale:
            REASON, STALE = stale, True
            return None
        LIB = _declare(lib)
        LIB_HELD = ctypes.PyDLL(path)
    except FileNotFoundError as e:
        REASON = str(e)
    except (OSError, AttributeError) as e:
        REASON = "%s cannot be loaded (%s); %s" % (LIBRARY, e, BUILD_HINT)
    return LIB


load()

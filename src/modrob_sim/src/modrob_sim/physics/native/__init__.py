"""Build (once, cached) and load the C hot loop ``modrob_ode_native.c`` with ctypes.

The library is compiled from the source next to this file with the system C compiler against
Debian's libode-dev (no other dependency), into ``$MODROB_NATIVE_DIR`` or
``$XDG_CACHE_HOME/modrob_sim`` (default ``~/.cache/modrob_sim``), named by the hash of the source,
the compiler flags and the ODE version, so an edited source or a new libode rebuilds it. Building
takes about a second, once per machine. Set ``MODROB_PHYSICS_NATIVE=0`` to use the pure-Python
path (same semantics, slower; triangle meshes then collide as their bounding boxes).

:data:`LIB` is the loaded library or None; :data:`REASON` says why it is None.
"""
import ctypes
import hashlib
import logging
import os
import subprocess
import tempfile

from .. import odelib

LOG = logging.getLogger("modrob_sim.physics")

SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "modrob_ode_native.c")
CFLAGS = ["-O2", "-fPIC", "-shared", "-std=c99", "-DdDOUBLE", "-Wall"]

LIB = None
REASON = None


def _cache_dir():
    d = os.environ.get("MODROB_NATIVE_DIR")
    if d:
        return d
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "modrob_sim")


def _ode_flags():
    try:
        out = subprocess.run(["pkg-config", "--cflags", "--libs", "ode"], capture_output=True,
                             text=True, timeout=20)
        if out.returncode == 0:
            return out.stdout.split()
    except (OSError, subprocess.SubprocessError):
        pass
    return ["-lode"]


def _ode_version():
    try:
        out = subprocess.run(["pkg-config", "--modversion", "ode"], capture_output=True, text=True,
                             timeout=20)
        return out.stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "?"


def build(force=False):
    """Compile the library if needed; return its path (raises RuntimeError with the compiler
    output on failure)."""
    with open(SOURCE, "rb") as f:
        src = f.read()
    flags = CFLAGS + _ode_flags()
    key = hashlib.sha256(src + " ".join(flags).encode() + _ode_version().encode()).hexdigest()[:16]
    d = _cache_dir()
    path = os.path.join(d, "libmodrob_ode_native-%s.so" % key)
    if os.path.exists(path) and not force:
        return path
    os.makedirs(d, exist_ok=True)
    cc = os.environ.get("CC", "cc")
    fd, tmp = tempfile.mkstemp(suffix=".so", dir=d)
    os.close(fd)
    cmd = [cc] + CFLAGS + ["-o", tmp, SOURCE] + _ode_flags() + ["-lm"]
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    except (OSError, subprocess.SubprocessError) as e:
        os.unlink(tmp)
        raise RuntimeError("cannot run the C compiler '%s': %s" % (cc, e))
    if res.returncode != 0:
        os.unlink(tmp)
        raise RuntimeError("compiling %s failed:\n%s" % (SOURCE, res.stderr[-2000:]))
    os.replace(tmp, path)  # atomic: concurrent builders cannot see a half-written file
    LOG.info("built the native physics loop: %s", path)
    return path


def _declare(lib):
    vp, i, d, ul = ctypes.c_void_p, ctypes.c_int, ctypes.c_double, ctypes.c_ulong
    sig = {
        "mr_ctx_new": (vp, [vp, vp, vp]),
        "mr_ctx_free": (None, [vp]),
        "mr_set_geom": (None, [vp, vp, i, i, i, i, i]),
        "mr_remove_geom": (None, [vp, vp]),
        "mr_set_surface": (None, [vp, i, d, d, d, d, d, d, d, d, d]),
        "mr_clear_adjacency": (None, [vp]),
        "mr_add_adjacent": (None, [vp, i, i, i]),
        "mr_set_model_count": (None, [vp, i]),
        "mr_model_contacts": (i, [vp, i]),
        "mr_last_contacts": (i, [vp]),
        "mr_contact_log": (i, [vp, vp, vp, i]),
        "mr_collide": (i, [vp, d, d, d, d, d, i]),
        "mr_quickstep": (ul, [vp, d, ul]),
        "mr_step": (i, [vp, d, d, d, d, d, i]),
        "mr_set_seed": (None, [vp, ul]),
        "mr_get_seed": (ul, [vp]),
        "mr_max_model_contacts": (i, [vp, ctypes.POINTER(ctypes.c_int)]),
        "mr_check_bodies": (i, [vp, i, i, d, d]),
        "mr_apply_damping": (None, [vp, vp, vp, i]),
        "mr_mesh_create": (vp, [vp, vp, i, vp, i, i]),
        "mr_mesh_destroy": (None, [vp, vp]),
        "mr_geom_set_body": (None, [vp, vp]),
        "mr_geom_set_offset": (None, [vp, d, d, d, d, d, d, d]),
        "mr_geom_set_pose": (None, [vp, d, d, d, d, d, d, d]),
        "mr_geom_set_bits": (None, [vp, ul, ul]),
        "mr_geom_aabb": (None, [vp, vp]),
        "mr_max_depth": (d, [vp, vp]),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype = res
        f.argtypes = args
    return lib


def load():
    global LIB, REASON
    if os.environ.get("MODROB_PHYSICS_NATIVE", "1").strip().lower() in ("0", "false", "no", "off"):
        REASON = "disabled by MODROB_PHYSICS_NATIVE=0"
        return None
    if not odelib.AVAILABLE:
        REASON = "PyODE's object layout could not be verified"
        return None
    try:
        path = build()
        LIB = _declare(ctypes.CDLL(path))
    except (RuntimeError, OSError, AttributeError) as e:
        REASON = str(e)
        LOG.warning("native physics loop unavailable (%s): using the pure-Python path (slower; "
                    "meshes collide as boxes)", e)
        LIB = None
    return LIB


load()

"""Build (once, cached) and load ``modrob_raycast.c`` with ctypes, the same way as the physics'
native loop (:mod:`modrob_sim.physics.native`): compiled against Debian's libode-dev into the same
cache directory, named by the hash of the source, the flags and the ODE version.

:data:`LIB` is the loaded library or None; :data:`REASON` says why it is None (the ray sensors
then use the numpy caster, which knows boxes, spheres, cylinders, capsules and planes only).
"""
import ctypes
import hashlib
import logging
import os
import subprocess
import tempfile

from modrob_sim.physics import native as physics_native

LOG = logging.getLogger("modrob_sim.sensors")
SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "modrob_raycast.c")
CFLAGS = ["-O2", "-fPIC", "-shared", "-std=gnu99", "-DdDOUBLE", "-Wall"]

LIB = None
REASON = None


def build(force=False):
    with open(SOURCE, "rb") as f:
        src = f.read()
    flags = CFLAGS + physics_native._ode_flags()
    stamp = src + " ".join(flags).encode() + physics_native._ode_version().encode()
    key = hashlib.sha256(stamp).hexdigest()[:16]
    d = physics_native._cache_dir()
    path = os.path.join(d, "libmodrob_raycast-%s.so" % key)
    if os.path.exists(path) and not force:
        return path
    os.makedirs(d, exist_ok=True)
    cc = os.environ.get("CC", "cc")
    fd, tmp = tempfile.mkstemp(suffix=".so", dir=d)
    os.close(fd)
    cmd = [cc] + CFLAGS + ["-o", tmp, SOURCE] + physics_native._ode_flags() + ["-lm"]
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    except (OSError, subprocess.SubprocessError) as e:
        os.unlink(tmp)
        raise RuntimeError("cannot run the C compiler '%s': %s" % (cc, e))
    if res.returncode != 0:
        os.unlink(tmp)
        raise RuntimeError("compiling %s failed:\n%s" % (SOURCE, res.stderr[-2000:]))
    os.replace(tmp, path)
    LOG.info("built the native ray caster: %s", path)
    return path


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
        LIB = _declare(ctypes.CDLL(build()))
    except (RuntimeError, OSError, AttributeError) as e:
        REASON = str(e)
        LOG.warning("native ray caster unavailable (%s): ray sensors use the numpy caster", e)
        LIB = None
    return LIB


load()

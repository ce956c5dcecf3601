"""Batched ray casting against the geometry the physics collides with.

Two casters with one interface, ``cast(origin, rotation, local_dirs, rmin, rmax) -> ranges`` and
``prepare(...)`` -> a cast whose ``run()`` returns them, later and in another thread if need be:

* :class:`OdeRayCaster` (default): ODE's own ray collider on the World's geoms, driven from C
  (``native/modrob_raycast.c``): the same boxes, spheres, cylinders, capsules, planes and triangle
  meshes as the physics by construction.
* :class:`NumpyRayCaster` (baseline and fallback): vectorised numpy intersection with the
  analytic shapes; triangle meshes count as their bounding boxes.

Ranges are distances from the sensor origin to the first hit along each ray in [rmin, rmax],
``inf`` where nothing is hit (the sensor model then masks and adds noise, see ray_sensor.py).
The geoms of the links in ``exclude`` (the sensor's own link) are not seen.
"""
import ctypes
import threading

import numpy as np
import ode

from modrob_sim.physics import backends

from . import native

NATIVE_AVAILABLE = native.LIB is not None


def world_geoms(world):
    """[(geom, model name, link name)] of every collision geom in the World, in spawn order."""
    return world.collision_geoms()


class _GeomCache(object):
    """The World's geom list, rebuilt when models come or go."""

    def __init__(self, world):
        self.world = world
        self._key = None
        self.entries = []

    def current(self):
        key = (self.world.geom_count, self.world.layout_version)
        if key != self._key:
            self.entries = world_geoms(self.world)
            self._key = key
            return True
        return False


class OdeRayCaster(object):
    """ODE's ray collider from C. ``exclude``: iterable of (model name, link name)."""

    name = "ode"

    def __init__(self, world, exclude=()):
        if not NATIVE_AVAILABLE:
            raise RuntimeError("the native ray caster is unavailable: %s" % native.REASON)
        self._cache = _GeomCache(world)
        self._exclude = set(exclude)
        self._ptrs = None
        self.labels = []
        self._angles = (None, None, None)     # (local_dirs, azimuth bins, elevations) of the last cast

    def _refresh(self):
        if self._cache.current() or self._ptrs is None:
            kept = [(g, m, ln) for g, m, ln in self._cache.entries if (m, ln) not in self._exclude]
            self.labels = [(m, ln) for _, m, ln in kept]
            self._geoms = [g for g, _, _ in kept]   # keeps the PyODE objects alive while cast
            self._ptrs = (ctypes.c_void_p * max(1, len(kept)))(*[backends.geom_ptr(g) for g in self._geoms])

    def _ray_angles(self, local_dirs, dirs):
        """The rays' azimuth bins and elevations in the sensor frame (modrob_raycast.c's
        rc_ray_angles), kept while the caller casts the same directions array (a sensor's rays)."""
        kept, bins, els = self._angles
        if kept is not local_dirs:
            n = dirs.shape[0]
            bins, els = np.empty(n, dtype=np.int32), np.empty(n, dtype=np.float64)
            native.LIB.rc_ray_angles(dirs.ctypes.data, n, bins.ctypes.data, els.ctypes.data)
            if local_dirs is dirs and not dirs.flags.writeable:
                self._angles = (local_dirs, bins, els)
        return bins, els

    def cast(self, origin, rotation, local_dirs, rmin, rmax, want_hits=False):
        """Ranges along R * local_dirs (a read-only array given again from cast to cast keeps its
        rays' angles: a sensor's fixed directions)."""
        return self._prepare(origin, rotation, local_dirs, rmin, rmax, want_hits, later=False).run()

    def prepare(self, origin, rotation, local_dirs, rmin, rmax, want_hits=False):
        """cast() in two halves: the geometry of this instant now, the rays when the returned
        PreparedCast's ``run()`` is called, which may be later and in another thread (the World
        steps meanwhile). With a triangle mesh (or another shape ODE collides through caches shared
        between threads) in reach, the rays are cast now, here."""
        return self._prepare(origin, rotation, local_dirs, rmin, rmax, want_hits, later=True)

    def _prepare(self, origin, rotation, local_dirs, rmin, rmax, want_hits, later):
        self._refresh()
        dirs = np.ascontiguousarray(local_dirs, dtype=np.float64)
        n = dirs.shape[0]
        bins, els = self._ray_angles(local_dirs, dirs)
        o = np.ascontiguousarray(origin, dtype=np.float64)
        r = np.ascontiguousarray(rotation, dtype=np.float64).reshape(9)
        handle = native.LIB.rc_prepare(self._ptrs, len(self._geoms), o.ctypes.data, r.ctypes.data,
                                       dirs.ctypes.data, n, float(rmin), float(rmax), bins.ctypes.data,
                                       els.ctypes.data, 1 if later else 0)
        if not handle:
            raise MemoryError("ray caster: out of memory for %d geoms" % len(self._geoms))
        # the C side points into the rays' arrays until it casts them; into the World's geoms only
        # when it casts now (a deferred cast has copies of its own)
        cast = PreparedCast(handle, n, want_hits, keep=(dirs, bins, els), labels=self.labels)
        if not later or native.LIB.rc_needs_now(handle):
            cast.run()
        return cast


class PreparedCast(object):
    """One cast's geometry at the instant it was prepared; ``run()`` casts its rays (once; again
    returns the same arrays) and may be called from any thread. ``labels``: the (model, link) of
    each hit index."""

    def __init__(self, handle, n, want_hits, keep, labels):
        self._handle = handle
        self._n = n
        self._want_hits = want_hits
        self._keep = keep          # what the C side points into, alive until the rays are cast
        self._free = native.LIB.rc_release     # kept: __del__ may run while the interpreter ends
        self.labels = labels
        self._result = None
        self._lock = threading.Lock()

    @property
    def deferred(self):
        """True while the rays wait for ``run()`` (False: cast when prepared)."""
        return self._result is None

    def run(self):
        with self._lock:
            if self._result is None:
                out = np.empty(self._n, dtype=np.float64)
                hits = np.empty(self._n, dtype=np.int32) if self._want_hits else None
                hit_ptr = hits.ctypes.data if hits is not None else None
                rc = native.LIB.rc_run(self._handle, out.ctypes.data, hit_ptr)
                self._release()
                if rc < 0:
                    raise MemoryError("ray caster: out of memory for %d rays" % self._n)
                self._result = (out, hits) if self._want_hits else out
            return self._result

    def _release(self):
        if self._handle:
            self._free(self._handle)
            self._handle = None
            self._keep = None

    def __del__(self):
        self._release()


class _Done(object):
    """A PreparedCast whose rays were cast when it was made (the numpy caster's)."""

    deferred = False

    def __init__(self, result, labels):
        self._result = result
        self.labels = labels

    def run(self):
        return self._result


# ---- numpy baseline ---------------------------------------------------------------------------
def _rot(geom):
    r = geom.getRotation()
    return np.array(r, dtype=np.float64).reshape(3, 3)


def _shape(geom):
    """(kind, params, position, rotation) of a geom for the numpy caster."""
    if isinstance(geom, ode.GeomPlane):
        n, d = geom.getParams()
        return "plane", (np.array(n, dtype=np.float64), float(d)), None, None
    if isinstance(geom, backends.NativeMesh):
        lo_hi = geom.getAABB()
        lo, hi = np.array(lo_hi[0::2]), np.array(lo_hi[1::2])
        return "box", (hi - lo), 0.5 * (lo + hi), np.eye(3)
    pos = np.array(geom.getPosition(), dtype=np.float64)
    rot = _rot(geom)
    if isinstance(geom, ode.GeomBox):
        return "box", np.array(geom.getLengths(), dtype=np.float64), pos, rot
    if isinstance(geom, ode.GeomSphere):
        return "sphere", float(geom.getRadius()), pos, rot
    if isinstance(geom, ode.GeomCylinder):
        r, length = geom.getParams()
        return "cylinder", (float(r), float(length)), pos, rot
    if isinstance(geom, ode.GeomCapsule):
        r, length = geom.getParams()
        return "capsule", (float(r), float(length)), pos, rot
    lo_hi = geom.getAABB()
    lo, hi = np.array(lo_hi[0::2]), np.array(lo_hi[1::2])
    return "box", (hi - lo), 0.5 * (lo + hi), np.eye(3)


def _hit_box(o, d, size):
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / d
        h = 0.5 * size
        a = (-h - o) * inv
        b = (h - o) * inv
        lo = np.nanmax(np.minimum(a, b), axis=1)
        hi = np.nanmin(np.maximum(a, b), axis=1)
    t = np.where(lo >= 0, lo, hi)     # from inside: the exit face, as ODE does
    ok = (hi >= lo) & (hi >= 0)
    return np.where(ok, t, np.inf)


def _hit_sphere(o, d, r, center=None):
    oc = o if center is None else o - center
    b = np.einsum("ij,ij->i", oc, d) if oc.ndim == 2 else d @ oc
    c = (oc * oc).sum(axis=-1) - r * r
    disc = b * b - c
    s = np.sqrt(np.maximum(disc, 0))
    t1, t2 = -b - s, -b + s
    t = np.where(t1 >= 0, t1, t2)
    return np.where((disc >= 0) & (t >= 0), t, np.inf)


class NumpyRayCaster(object):
    """Vectorised numpy intersection with the analytic shapes of the World's geoms."""

    name = "numpy"

    def __init__(self, world, exclude=()):
        self._cache = _GeomCache(world)
        self._exclude = set(exclude)

    @property
    def labels(self):
        return [(m, ln) for _, m, ln in self._cache.entries]

    def prepare(self, origin, rotation, local_dirs, rmin, rmax, want_hits=False):
        """cast() now (OdeRayCaster.prepare's interface)."""
        result = self.cast(origin, rotation, local_dirs, rmin, rmax, want_hits)
        return _Done(result, self.labels)

    def cast(self, origin, rotation, local_dirs, rmin, rmax, want_hits=False):
        self._cache.current()
        o = np.asarray(origin, dtype=np.float64)
        R = np.asarray(rotation, dtype=np.float64).reshape(3, 3)
        d = np.asarray(local_dirs, dtype=np.float64) @ R.T
        d /= np.linalg.norm(d, axis=1)[:, None]
        s = o + rmin * d                      # rays start at rmin, as Gazebo's
        length = rmax - rmin
        best = np.full(d.shape[0], np.inf)
        hits = np.full(d.shape[0], -1, dtype=np.int32)
        for idx, (g, m, ln) in enumerate(self._cache.entries):
            if (m, ln) in self._exclude:
                continue
            kind, p, pos, rot = _shape(g)
            if kind == "plane":
                n, dist = p
                with np.errstate(divide="ignore", invalid="ignore"):
                    t = (dist - s @ n) / (d @ n)
                t = np.where((t >= 0) & np.isfinite(t), t, np.inf)
            else:
                # cull: bounding sphere out of reach
                rad = {"box": lambda: 0.5 * float(np.linalg.norm(p)), "sphere": lambda: p,
                       "cylinder": lambda: float(np.hypot(p[0], 0.5 * p[1])),
                       "capsule": lambda: p[0] + 0.5 * p[1]}[kind]()
                if np.linalg.norm(pos - o) - rad > rmax:
                    continue
                ol = (s - pos) @ rot            # ray starts in the shape's frame
                dl = d @ rot
                if kind == "box":
                    t = _hit_box(ol, dl, p)
                elif kind == "sphere":
                    t = _hit_sphere(ol, dl, p)
                elif kind == "cylinder":
                    t = _hit_cylinder_many(ol, dl, p[0], p[1])
                else:
                    t = _hit_cylinder_many(ol, dl, p[0], p[1], caps=False)
                    for zc in (-0.5 * p[1], 0.5 * p[1]):
                        t = np.minimum(t, _hit_sphere(ol, dl, p[0], center=np.array([0.0, 0.0, zc])))
            better = (t <= length) & (t < best)
            best = np.where(better, t, best)
            hits = np.where(better, idx, hits)
        out = np.where(np.isfinite(best), rmin + best, np.inf)
        return (out, hits) if want_hits else out


def _hit_cylinder_many(o, d, r, length, caps=True):
    """Like _hit_cylinder with one start point per ray (o is (n, 3))."""
    h = 0.5 * length
    a = d[:, 0] ** 2 + d[:, 1] ** 2
    b = o[:, 0] * d[:, 0] + o[:, 1] * d[:, 1]
    c = o[:, 0] ** 2 + o[:, 1] ** 2 - r * r
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = b * b - a * c
        s = np.sqrt(np.maximum(disc, 0))
        t1 = (-b - s) / a
        t2 = (-b + s) / a
    best = np.full(d.shape[0], np.inf)
    for t in (t1, t2):
        z = o[:, 2] + t * d[:, 2]
        ok = (disc >= 0) & (a > 1e-15) & (t >= 0) & (np.abs(z) <= h)
        best = np.where(ok & (t < best), t, best)
    if caps:
        with np.errstate(divide="ignore", invalid="ignore"):
            for zc in (-h, h):
                t = (zc - o[:, 2]) / d[:, 2]
                x = o[:, 0] + t * d[:, 0]
                y = o[:, 1] + t * d[:, 1]
                ok = (t >= 0) & (x * x + y * y <= r * r)
                best = np.where(ok & (t < best), t, best)
    return best


def make_caster(world, exclude=(), kind=None):
    """The ODE caster when the native library is available (or ``kind="ode"``), else numpy; a
    library built from another source (sensors.native.STALE): RuntimeError saying to build."""
    if kind is None and native.STALE:
        raise RuntimeError(native.REASON)
    if kind == "numpy" or (kind is None and not NATIVE_AVAILABLE):
        return NumpyRayCaster(world, exclude)
    return OdeRayCaster(world, exclude)

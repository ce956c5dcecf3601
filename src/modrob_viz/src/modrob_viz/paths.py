"""Sample work-space paths (the seed's dummy trajectories): circle, line, helix, figure eight.
The defaults lie in the reach of the 4-DoF demo robot (base at the origin, 1.4 m tall).

Every generator returns a list of (x, y, z) tuples [m]; ``n`` is the number of points.
"""
import math

from modrob_viz.errors import TrajectoryError


def _check(n, **values):
    if int(n) != n or n < 2:
        raise TrajectoryError("a path needs n >= 2 points, got %r" % (n,))
    for name, v in values.items():
        for x in (v if isinstance(v, (list, tuple)) else [v]):
            if not math.isfinite(float(x)):
                raise TrajectoryError("path parameter '%s' is not finite (%r)" % (name, v))


def circle(center=(0.4, 0.0, 0.8), radius=0.15, n=100):
    """A closed circle in the horizontal plane through ``center`` (first point = last point)."""
    _check(n, center=center, radius=radius)
    cx, cy, cz = center
    return [(cx + radius * math.cos(2 * math.pi * i / (n - 1)),
             cy + radius * math.sin(2 * math.pi * i / (n - 1)), cz) for i in range(n)]


def line(start=(0.4, -0.3, 0.6), end=(0.4, 0.3, 1.0), n=50):
    """A straight line from ``start`` to ``end``."""
    _check(n, start=start, end=end)
    return [tuple(s + (e - s) * i / (n - 1) for s, e in zip(start, end)) for i in range(n)]


def helix(center=(0.45, 0.0, 0.5), radius=0.15, pitch=0.1, turns=3.0, n=200):
    """A helix about the vertical axis through ``center``, rising ``pitch`` per turn."""
    _check(n, center=center, radius=radius, pitch=pitch, turns=turns)
    cx, cy, cz = center
    out = []
    for i in range(n):
        a = 2 * math.pi * turns * i / (n - 1)
        out.append((cx + radius * math.cos(a), cy + radius * math.sin(a), cz + pitch * a / (2 * math.pi)))
    return out


def figure_eight(center=(0.4, 0.0, 0.9), size=0.2, n=150):
    """A lemniscate of Gerono in the vertical y-z plane through ``center`` (closed)."""
    _check(n, center=center, size=size)
    cx, cy, cz = center
    out = []
    for i in range(n):
        a = 2 * math.pi * i / (n - 1)
        out.append((cx, cy + size * math.sin(a), cz + size * math.sin(a) * math.cos(a)))
    return out


GENERATORS = {"circle": circle, "line": line, "helix": helix, "figure_eight": figure_eight}


def generate(shape, **kwargs):
    """Points of the named shape; unknown shapes and parameters are refused with the choices."""
    if shape not in GENERATORS:
        raise TrajectoryError("unknown path shape '%s': choose one of %s"
                              % (shape, ", ".join(sorted(GENERATORS))))
    func = GENERATORS[shape]
    try:
        return func(**kwargs)
    except TypeError as err:
        raise TrajectoryError("bad parameters for shape '%s': %s" % (shape, err))

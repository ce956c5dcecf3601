"""Minimum distance between robot bases in the x-y plane (seed section IV-E, corrected).

For a pair (i, j), i < j, whose bases are closer than d_min in the x-y plane, the later robot j is
moved along the line from base i through base j until the distance is d_min:

    dp        = |base_j - base_i|_xy                                  (seed eq. 9)
    base_j'   = base_i + d_min / dp * (base_j - base_i)   (x and y)   (seed eq. 10, with the ratio
                                                                       the right way up)

z (and yaw) are kept. Coincident bases (dp = 0) have no line: robot j then moves along +x.
Pairs are visited in index order and the sweep is repeated until no pair conflicts; robot 0
never moves. d_min = 0 (the default) switches the feature off.
"""
import math

from modrob_build.errors import LayoutError

COINCIDENT = 1e-9


def _xy_distance(a, b):
    return math.hypot(b[0] - a[0], b[1] - a[1])


def enforce_safety_distance(bases, d_min, max_sweeps=None, tolerance=1e-9, names=None):
    """(new_bases, messages). bases: sequence of (x, y, z, ...) tuples; d_min in metres; names
    of the robots for the messages (default modrob0, modrob1, ...).

    Raises LayoutError for a negative or non-finite d_min or when no layout is found."""
    d_min = float(d_min)
    if not math.isfinite(d_min) or d_min < 0.0:
        raise LayoutError("safety_distance must be a finite number >= 0 (0 = off), not %r" % d_min)
    bases = [tuple(float(v) for v in b) for b in bases]
    messages = []
    if d_min == 0.0 or len(bases) < 2:
        return bases, messages
    n = len(bases)
    names = list(names) if names else ["modrob%d" % i for i in range(n)]
    max_sweeps = max_sweeps or 10 * n * n + 10
    for _ in range(max_sweeps):
        moved = False
        for i in range(n):
            for j in range(i + 1, n):
                dp = _xy_distance(bases[i], bases[j])
                if dp >= d_min - tolerance:
                    continue
                bi, bj = bases[i], bases[j]
                if dp < COINCIDENT:
                    new_xy = (bi[0] + d_min, bi[1])
                    how = "coincident with %s: moved along +x" % names[i]
                else:
                    s = d_min / dp
                    new_xy = (bi[0] + s * (bj[0] - bi[0]), bi[1] + s * (bj[1] - bi[1]))
                    how = "%.3f m from %s: moved along the line between them" % (dp, names[i])
                bases[j] = new_xy + bj[2:]
                messages.append("safety distance %.3f m: %s base %s; (%.3f, %.3f) -> (%.3f, %.3f)"
                                % (d_min, names[j], how, bj[0], bj[1], new_xy[0], new_xy[1]))
                moved = True
        if not moved:
            return bases, messages
    raise LayoutError("safety distance %.3f m: no conflict-free layout of the %d bases found after %d "
                      "sweeps; place the bases further apart by hand" % (d_min, n, max_sweeps))


def min_pair_distance(bases):
    """Smallest x-y distance between any two bases (inf for fewer than two)."""
    best = math.inf
    for i in range(len(bases)):
        for j in range(i + 1, len(bases)):
            best = min(best, _xy_distance(bases[i], bases[j]))
    return best

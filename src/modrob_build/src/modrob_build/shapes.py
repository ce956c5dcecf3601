"""Mass properties of the primitive shapes the modules are made of (pure functions).

All inertias are about the centre of mass, in the shape's own frame, for a shape whose axis of
symmetry is z (cylinders) unless an axis is given. Units: SI (kg, m, kg m^2).
"""
import math


def solid_cylinder_inertia(mass, radius, length):
    """(ixx, iyy, izz) of a homogeneous solid cylinder whose axis is z."""
    side = mass * (3.0 * radius ** 2 + length ** 2) / 12.0
    return (side, side, 0.5 * mass * radius ** 2)


def tube_inertia(mass, outer_radius, inner_radius, length):
    """(ixx, iyy, izz) of a homogeneous thick-walled tube whose axis is z."""
    r2 = outer_radius ** 2 + inner_radius ** 2
    side = mass * (3.0 * r2 + length ** 2) / 12.0
    return (side, side, 0.5 * mass * r2)


def rotate_to_axis(inertia, axis):
    """A diagonal inertia given for a z-symmetric shape, re-expressed for a shape whose symmetry
    axis is 'x', 'y' or 'z' (principal axes stay aligned with the frame)."""
    side, _, along = inertia
    if axis == "x":
        return (along, side, side)
    if axis == "y":
        return (side, along, side)
    return (side, side, along)


class Part(object):
    """A point-symmetric lump: mass, centre (x, y, z) and diagonal inertia about its centre."""

    def __init__(self, mass, center, inertia):
        self.mass = float(mass)
        self.center = tuple(float(c) for c in center)
        self.inertia = tuple(float(i) for i in inertia)


def combine(parts):
    """Mass, centre of mass and diagonal inertia (about that centre) of rigidly joined parts whose
    principal axes are all aligned with the frame (parallel-axis theorem; the products of inertia
    vanish because every part's centre lies on the z axis of the frame in our modules)."""
    mass = sum(p.mass for p in parts)
    if mass <= 0.0:
        raise ValueError("parts without mass cannot be combined")
    com = tuple(sum(p.mass * p.center[k] for p in parts) / mass for k in range(3))
    ixx = iyy = izz = 0.0
    for p in parts:
        dx, dy, dz = (p.center[k] - com[k] for k in range(3))
        ixx += p.inertia[0] + p.mass * (dy * dy + dz * dz)
        iyy += p.inertia[1] + p.mass * (dx * dx + dz * dz)
        izz += p.inertia[2] + p.mass * (dx * dx + dy * dy)
    return mass, com, (ixx, iyy, izz)


def satisfies_triangle_inequality(inertia, tol=1e-12):
    """A physical diagonal inertia: each principal moment <= the sum of the other two."""
    a, b, c = inertia
    return (a > 0 and b > 0 and c > 0 and a <= b + c + tol and b <= a + c + tol
            and c <= a + b + tol and all(math.isfinite(x) for x in inertia))

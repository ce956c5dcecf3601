"""The magnitudes the simulator accepts, and the check of a whole model against them.

Everything here is checked before the first ODE object exists, because ODE answers an absurd
(even finite) number by aborting the process, which Python cannot catch:

* ODE's hash spaces turn each geom's bounding box into integer cell indices, ``floor(x / cell)``
  with cells down to 2^-3 m, and assert that they fit an ``int``
  (``aabbBound >= dMinIntExact``): anything beyond 2^31 / 8 = 2.7e8 m from the origin aborts
  ``collide()``. Positions the user gives are limited to LENGTH_LIMIT = 1e6 m (270 times below)
  and composed link positions to WORLD_EXTENT = 1e7 m.
* products of masses, inertias, lengths and forces must stay far from overflow (ODE's step
  squares and multiplies them); the limits below keep every product under about 1e30.

The numbers are documented in docs/simulator.md ("Limits"); every refusal names the model, the
link or joint, the field, the value and the limit.
"""
import math

from ..errors import InputError, ModelError

#: any position, offset or origin the user gives (m); sizes of shapes too
LENGTH_LIMIT = 1e6
#: where a link may be after composing origins (m); ODE's hash space aborts beyond ~2.7e8 m
WORLD_EXTENT = 1e7
#: smallest size of a shape (m): below it ODE's collision routines lose every digit
MIN_SIZE = 1e-6
#: a link's mass (kg)
MASS_LIMIT = 1e9
#: each inertia tensor entry (kg m^2)
INERTIA_LIMIT = 1e12
#: each component of a joint axis or plane normal, before normalisation (and its length >= this)
AXIS_MIN_LENGTH = 1e-9
#: joint <dynamics> damping (N s/m, N m s/rad) and friction (N, N m)
DYNAMICS_LIMIT = 1e9
#: |multiplier| of a <mimic> joint
MIMIC_MULTIPLIER_LIMIT = 1e3
#: contact stiffness kp (N/m) and damping kd (N s/m), friction coefficients, maxVel (m/s)
SURFACE_LIMIT = 1e20
#: each component of the world's gravity (m/s^2): 100 g
GRAVITY_LIMIT = 1e3
#: physics time step bounds (s)
MIN_TIME_STEP = 1e-6
MAX_TIME_STEP = 0.1
#: ODE steppers by Gazebo's <ode><solver><type>: quickStep (iterative, `iters` and `sor`) or the
#: exact dWorldStep (a Dantzig LCP per island, its cost grows with the cube of the island's rows)
SOLVER_TYPES = ("quick", "world")
#: physics parameters (World.set_physics_params, set_physics_properties' ode_config, SDF <ode>):
#: the largest value each may take (every one is also finite and >= 0)
PHYSICS_PARAM_MAX = {"iters": 10000, "sor": 2.0, "cfm": 1e6, "erp": 1.0,
                     "contact_max_correcting_vel": 1e6, "contact_surface_layer": 1.0,
                     "max_contacts": 1000, "guard_max_linear_velocity": 1e6,
                     "guard_max_angular_velocity": 1e7, "guard_max_contacts": 1e7,
                     "snapshot_interval": 1e6}
#: joint positions set by set_model_configuration / spawn -J for joints without limits (m or rad)
JOINT_POSITION_LIMIT = LENGTH_LIMIT

_SEE = " (limits: docs/simulator.md)"


def _fail(model, where, field, value, rule):
    raise ModelError("model '%s' %s: %s = %s %s%s" % (model, where, field, _fmt(value), rule, _SEE))


def _fmt(v):
    if isinstance(v, (tuple, list)):
        return "(%s)" % ", ".join("%.6g" % x for x in v)
    return "%.6g" % v


def check_position(model, where, field, p, limit=LENGTH_LIMIT):
    if not all(math.isfinite(x) for x in p):
        _fail(model, where, field, p, "is not finite")
    if max(abs(x) for x in p) > limit:
        _fail(model, where, field, p, "is beyond %g m" % limit)


def check_axis(model, where, field, a):
    """A direction: finite components of at most LENGTH_LIMIT, length at least AXIS_MIN_LENGTH
    (so that normalising neither overflows nor divides by ~0)."""
    if not all(math.isfinite(x) for x in a):
        _fail(model, where, field, a, "is not finite")
    big = max(abs(x) for x in a)
    if big > LENGTH_LIMIT:
        _fail(model, where, field, a, "has a component beyond %g: give a unit direction" % LENGTH_LIMIT)
    if math.sqrt(sum(x * x for x in a)) < AXIS_MIN_LENGTH:
        _fail(model, where, field, a, "has (nearly) zero length (< %g)" % AXIS_MIN_LENGTH)


def normalized_axis(a):
    n = math.sqrt(sum(x * x for x in a))
    return tuple(x / n for x in a)


def _check_range(model, where, field, v, lo, hi, unit, lo_open=False):
    if not math.isfinite(v) or v > hi or (v <= lo if lo_open else v < lo):
        _fail(model, where, field, v, "must be in %s%g, %g] %s" % ("(" if lo_open else "[", lo, hi, unit))


def _check_geometry(model, where, g):
    tag = "<%s>" % g.kind
    if g.kind in ("box", "sphere", "cylinder", "capsule"):
        names = {"box": ("size x", "size y", "size z"), "sphere": ("radius",),
                 "cylinder": ("radius", "length"), "capsule": ("radius", "length")}[g.kind]
        for name, v in zip(names, g.size):
            # a capsule of length 0 is a sphere; every other size must be positive
            lo = 0.0 if (g.kind == "capsule" and name == "length") else MIN_SIZE
            _check_range(model, where, "%s %s" % (tag, name), v, lo, LENGTH_LIMIT, "m")
    elif g.kind == "mesh":
        for v in g.size:
            if not math.isfinite(v) or abs(v) < MIN_SIZE or abs(v) > LENGTH_LIMIT:
                _fail(model, where, "<mesh> scale", g.size,
                      "needs every factor with %g <= |factor| <= %g" % (MIN_SIZE, LENGTH_LIMIT))
    elif g.kind == "plane":
        check_axis(model, where, "<plane> normal", g.size)
    check_position(model, where, "<origin xyz>", g.origin[0])


def validate_model(desc):
    """Refuse (ModelError) any number of ``desc`` beyond the limits above; returns ``desc``."""
    m = desc.name
    for ld in desc.links.values():
        where = "link '%s'" % ld.name
        if ld.has_inertial or ld.mass:
            _check_range(m, where, "<mass>", ld.mass, 0.0, MASS_LIMIT, "kg")
            check_position(m, where, "<inertial><origin xyz>", ld.inertial_origin[0])
            for name, v in zip(("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), ld.inertia):
                _check_range(m, where, "<inertia %s>" % name, v, -INERTIA_LIMIT, INERTIA_LIMIT, "kg m^2")
        if ld.pose is not None:
            check_position(m, where, "<pose>", ld.pose[0])
        for kind, geoms in (("collision", ld.collisions), ("visual", ld.visuals)):
            for g in geoms:
                _check_geometry(m, "%s <%s%s>" % (where, kind, " name='%s'" % g.name if g.name else ""), g)
        s = ld.surface
        for name, v in (("mu1", s.mu1), ("mu2", s.mu2), ("kp", s.kp), ("kd", s.kd),
                        ("maxVel", s.max_vel), ("minDepth", s.min_depth or 0.0)):
            _check_range(m, where, "<%s>" % name, v, 0.0, SURFACE_LIMIT, "")
    for jd in desc.joints.values():
        where = "joint '%s'" % jd.name
        check_position(m, where, "<origin xyz>", jd.origin[0])
        check_position(m, where, "child offset", jd.child_offset[0])
        if jd.type in ("revolute", "continuous", "prismatic", "planar"):
            check_axis(m, where, "<axis xyz>", jd.axis)
        _check_range(m, where, "<dynamics damping>", jd.damping, 0.0, DYNAMICS_LIMIT, "")
        _check_range(m, where, "<dynamics friction>", jd.friction, 0.0, DYNAMICS_LIMIT, "")
        for name, v in (("<limit lower>", jd.lower), ("<limit upper>", jd.upper)):
            if v is not None and not math.isfinite(v):
                _fail(m, where, name, v, "is not finite")
        if jd.mimic is not None:
            _check_range(m, where, "<mimic multiplier>", jd.mimic[1], -MIMIC_MULTIPLIER_LIMIT,
                         MIMIC_MULTIPLIER_LIMIT, "")
            _check_range(m, where, "<mimic offset>", jd.mimic[2], -LENGTH_LIMIT, LENGTH_LIMIT, "")
    if desc.pose is not None:
        check_position(m, "<pose>", "position", desc.pose[0])
    check_position(m, "root link", "pose", desc.root_offset[0])
    return desc


def check_link_extent(model, link, position):
    """Composed link positions (origins added along the tree and the spawn pose)."""
    check_position(model, "link '%s'" % link, "position in the world", position, WORLD_EXTENT)


def check_gravity(g, what="gravity"):
    """A gravity vector; ValueError naming ``what`` and the limit."""
    g = tuple(float(x) for x in g)
    if len(g) != 3 or not all(math.isfinite(x) for x in g) or max(abs(x) for x in g) > GRAVITY_LIMIT:
        raise InputError("%s = %s: each component must be finite and within +-%g m/s^2%s"
                         % (what, _fmt(g), GRAVITY_LIMIT, _SEE))
    return g


def check_time_step(dt, what="time_step"):
    try:
        dt = float(dt)
    except (TypeError, ValueError):
        raise InputError("%s must be a number of seconds, got %r" % (what, dt))
    if not (math.isfinite(dt) and MIN_TIME_STEP <= dt <= MAX_TIME_STEP):
        raise InputError("%s = %r s must be in [%g, %g] s%s"
                         % (what, dt, MIN_TIME_STEP, MAX_TIME_STEP, _SEE))
    return dt

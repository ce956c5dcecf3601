"""The World: an ODE world stepped in simulated time, with Gazebo-like contacts, step hooks and a
blow-up guard. See docs/physics.md for the design and sim_core_api.md for the contract."""
import hashlib
import logging
import math
import os
import random
import struct
import weakref
from collections import OrderedDict, namedtuple

import ode

from ..errors import InputError, ModelError, SimulationError
from . import actuators as actuators_mod
from . import limits
from . import meshes as meshlib
from . import native as native_mod
from . import odelib
from .backends import NativeBackend, NativeMesh, PureBackend  # noqa: F401 (NativeMesh: public name)
from .builder import build_model
from .contact_watch import ContactWatch
from .due import DUE_MARGIN, stops_at
from .description import GeometryDesc
from .model import FORCE_CAP, MIMIC_COUPLING_FORCE, MIMIC_GAIN  # noqa: F401 (public names)
from .transforms import (IDENTITY_POSE, check_pose, check_vec3, cross, dot, normalized, pose_mul,
                         quat_rotate, to_ode_quat)
from .urdf_reader import read_urdf
from .world_parts import WorldParts, may_sleep, warn_once

LOG = logging.getLogger("modrob_sim.physics")

GuardEvent = namedtuple("GuardEvent", "model link reason time")
#: one contact point of the last step (addition): model/link names of both sides, world position,
#: normal (pointing from the second geom into the first, ODE's convention), penetration depth, and
#: what the contact did in the step (ODE's joint feedback, world frame): force1/torque1 on side 1's
#: link (torque about its body's centre of mass), force2/torque2 on side 2's; a static side gets
#: the reaction of the other side's force, its torque about the static link's frame origin
ContactPoint = namedtuple("ContactPoint", "model1 link1 model2 link2 position normal depth "
                          "force1 torque1 force2 torque2")

#: Gazebo's ODE defaults, except max_contacts (Gazebo 20 per pair; ODE makes up to 8 for a
#: cylinder on a box, 4 spread points hold any resting face) and the guard settings (ours).
DEFAULT_PARAMS = OrderedDict([
    ("solver_type", "quick"),
    ("iters", 50),
    ("sor", 1.3),
    ("cfm", 0.0),
    ("erp", 0.2),
    ("contact_max_correcting_vel", 100.0),
    ("contact_surface_layer", 0.001),
    ("max_contacts", 4),
    ("auto_disable", True),
    ("guard_max_linear_velocity", 50.0),
    ("guard_max_angular_velocity", 500.0),
    ("guard_max_contacts", 2000),
    ("snapshot_interval", 50),
])

INF = float("inf")

#: restorations of one model, each within a second of the last, after which the guard freezes that
#: model (a model restored every step of a simulated second at 1 ms); the rest of the world goes on
GUARD_STREAK_LIMIT = 1000
#: the GuardEvent reason of the event that freezes a model
FROZEN_REASON = "frozen"

_ALL_BITS = (1 << 62) - 1
AUTO_DISABLE_LINEAR = 0.005   # m/s
AUTO_DISABLE_ANGULAR = 0.01   # rad/s
AUTO_DISABLE_TIME = 0.2       # s


class _ModelEntry(object):
    """What the World keeps about one of its models (the model itself knows nothing of it):
    collision filtering, the guard's snapshots and the native loop's ids."""
    __slots__ = ("model", "slot", "adjacent", "ncontacts", "uid", "cindex", "spawn_state",
                 "snapshot_state", "snapshot_iter")

    def __init__(self, model):
        self.model = model
        self.slot = 0                  # collision category bit (0: filtered in the callback)
        self.adjacent = frozenset()    # (group index, group index) pairs joined by a joint
        self.ncontacts = 0             # contacts of the last step (pure backend)
        self.uid = None                # native loop: unique model id
        self.cindex = None             # native loop: compact index (contact counters)
        self.spawn_state = None
        self.snapshot_state = None
        self.snapshot_iter = -1        # the iteration count at which snapshot_state was taken


class _GeomInfo(object):
    __slots__ = ("model", "link", "collision", "body", "surface", "self_collide", "group", "geom", "entry")

    def __init__(self, geom, entry, link, collision, surface, body):
        self.geom = geom
        self.entry = entry
        self.model = entry.model
        self.link = link
        self.collision = collision      # its <collision>'s name (Link.collision_names)
        self.body = body
        self.surface = surface
        self.self_collide = link.self_collide
        self.group = link.group.index


class World(object):
    """An ODE world. All times are simulated; nothing here reads the wall clock."""

    def __init__(self, time_step=0.001, gravity=(0.0, 0.0, -9.81), seed=0, resource_resolver=None,
                 native=None):
        """``native`` (addition): None = use the C hot loop when it is available, False = the
        pure-Python path, True = require the C loop (SimulationError if it cannot be built)."""
        # what the World shares with its backend (handed over once; the backend never sees the World)
        self._p = p = WorldParts()
        p.dt = self._check_dt(time_step)
        p.gravity = limits.check_gravity(check_vec3(gravity, "World gravity"), "World gravity")
        try:
            self._seed = int(seed)
        except (TypeError, ValueError):
            raise InputError("World seed must be an integer, got %r" % (seed,))
        self._resolver = resource_resolver
        self._p.ode_world = ode.World()
        self._p.ode_world.setGravity(self._p.gravity)
        # auto-disable (used only for free single-body models, see _apply_auto_disable): a body
        # sleeps after 0.2 s below 5 mm/s and 0.01 rad/s, so only bodies at rest or creeping
        # slower than ~0.025 m/s^2 from rest; contacts, wrenches and teleports wake it
        w = self._p.ode_world
        w.setAutoDisableFlag(False)
        w.setAutoDisableLinearThreshold(AUTO_DISABLE_LINEAR)
        w.setAutoDisableAngularThreshold(AUTO_DISABLE_ANGULAR)
        w.setAutoDisableSteps(10)
        w.setAutoDisableTime(AUTO_DISABLE_TIME)
        self._p.static_space = ode.HashSpace()
        self._p.dyn_space = ode.HashSpace()
        self._p.contact_group = ode.JointGroup()
        if native and native_mod.LIB is None:
            raise SimulationError("the native physics loop is not available: %s" % native_mod.REASON)
        if native is None and native_mod.STALE:      # not the pure-Python path unnoticed
            raise SimulationError(native_mod.REASON)
        self._p.params = OrderedDict(DEFAULT_PARAMS)
        self._p.entries = {}       # model -> _ModelEntry
        self._p.geom_info = {}
        self._p.warned = set()
        self._p.pair_cache = {}
        if native_mod.LIB is not None and native is not False:
            self._backend = NativeBackend(native_mod.LIB, self._p)
        else:
            self._backend = PureBackend(self._p)
        self._guard_log = {}     # model -> [last logged t, suppressed, streak, last restore t]
        self._frozen = OrderedDict()  # model name -> (Model, state it is held in, message)
        self.models = OrderedDict()
        self._hooks = OrderedDict()
        self._next_hook = 1
        self._before = ()
        self._after = ()
        self._before_dues = ()
        self._after_dues = ()
        self._effort_joints = []
        self._last_effort_joints = []
        self._actuators = []
        self._model_actuators = []
        self._wrench_links = _OrderedSet()
        self._watches = []       # (ContactWatch, its model) of watch_contacts
        self._events = []
        self._used_slots = set()
        self._mesh_cache = {}
        self.time = 0.0
        self.iterations = 0
        #: (addition) steps made in native stretches, without Python (statistics, tests)
        self.native_steps = 0
        #: (addition) steps made natively after their before-hooks ran in Python (statistics,
        #: tests); the steps made in Python are iterations - native_steps - hooked_steps
        self.hooked_steps = 0
        self._last_stretch = 0          # steps of the last native stretch World.advance saw
        #: (addition) the steps at which hooks ran in Python: a before-hook due at the step's start,
        #: after-hooks due at its end (one each), every step made in Python (statistics, the node's
        #: log, tests)
        self.stops = 0
        #: (addition) how many times reset_world ran (reset() included): a helper that keeps state
        #: between its due times (the <gripper> check) notices a reset by it at its next due time
        self.reset_count = 0
        self._ncontacts = 0
        # Tear the ODE objects down in a safe order when the World goes (or on close()): PyODE
        # objects freed by the cycle collector in arbitrary order crash (a space or world freed
        # before its geoms/bodies). Models refer to the World only weakly, so this runs first.
        self._finalizer = weakref.finalize(self, _teardown, self.models, self._p, self._backend)
        self.layout_version = 0
        self._reseed()
        self._apply_params()
        self._rebuild_caches()

    # ---- properties --------------------------------------------------------------------------
    @staticmethod
    def _check_dt(dt):
        return limits.check_time_step(dt)

    @property
    def time_step(self):
        return self._p.dt

    @time_step.setter
    def time_step(self, dt):
        self._p.dt = self._check_dt(dt)
        self._p.pair_cache.clear()
        self._rebuild_caches()  # the damping bound depends on dt

    @property
    def gravity(self):
        return self._p.gravity

    @gravity.setter
    def gravity(self, g):
        self._p.gravity = limits.check_gravity(check_vec3(g, "World gravity"), "World gravity")
        self._p.ode_world.setGravity(self._p.gravity)
        self._backend.settings_changed()
        for m in self.models.values():
            m.wake()

    @property
    def seed(self):
        return self._seed

    @property
    def rng(self):
        """The world's seeded random generator (random.Random): use it for anything random."""
        return self._rng

    @property
    def physics_params(self):
        return dict(self._p.params)

    def set_physics_params(self, **kw):
        new = OrderedDict(self._p.params)
        for k, v in kw.items():
            if k not in new:
                raise InputError("unknown physics parameter '%s' (known: %s)" % (k, ", ".join(new)))
            if k == "auto_disable":
                new[k] = bool(v)
                continue
            if k == "solver_type":
                if v not in limits.SOLVER_TYPES:
                    raise InputError("physics parameter solver_type=%r: must be 'quick' (ODE quickStep, "
                                     "Gazebo's default) or 'world' (ODE's exact dWorldStep)" % (v,))
                new[k] = v
                continue
            try:
                v = float(v)
            except (TypeError, ValueError):
                raise InputError("physics parameter %s=%r is not a number" % (k, v))
            if not math.isfinite(v) or v < 0:
                raise InputError("physics parameter %s=%r must be finite and not negative" % (k, v))
            top = limits.PHYSICS_PARAM_MAX.get(k)
            if top is not None and v > top:
                raise InputError("physics parameter %s=%r is beyond %g (limits: docs/simulator.md)"
                                 % (k, v, top))
            if k in ("iters", "max_contacts", "guard_max_contacts", "snapshot_interval"):
                if v < 1:
                    raise InputError("physics parameter %s must be at least 1" % k)
                v = int(v)
            new[k] = v
        self._p.params = new
        self._apply_params()

    def _apply_params(self):
        p = self._p.params
        w = self._p.ode_world
        w.setQuickStepNumIterations(int(p["iters"]))
        w.setERP(p["erp"])
        w.setCFM(p["cfm"])
        w.setContactMaxCorrectingVel(p["contact_max_correcting_vel"])
        # Gazebo's ODE fork takes a contact's allowed penetration from its bodies' minDepth, not
        # from the world's surface layer (every moving link has one, 0 by default): the contact
        # callbacks subtract minDepth themselves, and ODE's own layer stays 0
        w.setContactSurfaceLayer(0.0)
        if odelib.AVAILABLE:
            odelib.LIB.dWorldSetQuickStepW(odelib.raw_pointer(w), p["sor"])
        self._p.world_step = 1 if p["solver_type"] == "world" else 0
        self._p.max_contacts = int(p["max_contacts"])
        self._p.layer = float(p["contact_surface_layer"])
        self._p.vmax2 = p["guard_max_linear_velocity"] ** 2
        self._p.wmax2 = p["guard_max_angular_velocity"] ** 2
        self._p.pair_cache.clear()
        self._backend.settings_changed()
        for m in self.models.values():
            self._apply_auto_disable(m)

    def may_sleep(self, model):
        """Whether ``model``'s body may fall asleep: only a free single-body model, and only while the
        world's auto_disable is on."""
        return may_sleep(model, self._p.params)

    def _apply_auto_disable(self, model):
        """Auto-disable (as Gazebo's allow_auto_disable) only for free single-body models: an
        articulated robot under control must never fall asleep."""
        bodies = model.bodies
        on = self.may_sleep(model)
        for b in bodies:
            _set_auto_disable(b, on)

    def _reseed(self):
        self._rng = random.Random(self._seed)
        self._backend.set_seed(self._seed & 0xFFFFFFFF)

    def collision_geoms(self):
        """(addition) [(geom, model name, link name)] of every collision geom, in spawn order (the
        ray sensors cast against them)."""
        return [(g, i.model.name, i.link.name) for g, i in self._p.geom_info.items()]

    @property
    def geom_count(self):
        """(addition) How many geoms the World's collision tables hold (a refused model leaves none)."""
        return len(self._p.geom_info)

    @property
    def native(self):
        """True when the C hot loop steps this world (addition)."""
        return self._backend.native

    def close(self):
        """Free the ODE objects now (addition; otherwise when the World is collected). The World
        cannot be used afterwards."""
        self._finalizer()

    # ---- hooks -------------------------------------------------------------------------------
    def add_step_hook(self, before=None, after=None, before_due=None, after_due=None):
        """``before(t, dt)`` before the physics of a step starting at t, ``after(t, dt)`` after
        that of a step ending at t. ``before_due()`` / ``after_due()`` (optional): the simulated
        time from which the hook next has work; the World calls it no later than at the first
        step with t + 1e-9 >= that time (steps natively until then) and may call it earlier.
        Without one the hook runs at every step. docs/design/sim_core_api.md, "Step hooks and
        due times"."""
        if before is None and after is None:
            raise InputError("add_step_hook needs before and/or after")
        for f, n in ((before, "before"), (after, "after"), (before_due, "before_due"),
                     (after_due, "after_due")):
            if f is not None and not callable(f):
                raise InputError("add_step_hook: %s=%r is not callable" % (n, f))
        handle = self._next_hook
        self._next_hook += 1
        self._hooks[handle] = (before, after, before_due if before is not None else None,
                               after_due if after is not None else None)
        self._update_hooks()
        return handle

    def wake(self):
        """The one World method any thread may call: work was stored for a hook (a ROS callback),
        so a native stretch in progress ends after its current step and the due times are asked
        again."""
        self._backend.wake()

    def set_step_observer(self, fn, user):
        """A C function ``void fn(void *user, double t)`` (addresses, as ctypes gives them; None:
        none) that the native backend calls after every step it makes without Python, with the
        new simulated time (the /gazebo node's /clock through roscpp). The steps made in Python
        call the hooks instead; the pure-Python backend never calls it."""
        self._backend.set_observer(fn, user)

    @property
    def step_hook_count(self):
        """How many step hooks are registered (addition)."""
        return len(self._hooks)

    def remove_step_hook(self, handle):
        if handle not in self._hooks:
            raise InputError("no step hook with handle %r" % (handle,))
        del self._hooks[handle]
        self._update_hooks()

    def _update_hooks(self):
        hooks = list(self._hooks.values())
        self._before = tuple(h[0] for h in hooks if h[0] is not None)
        self._after = tuple(h[1] for h in hooks if h[1] is not None)
        # a hook without a due function is due at every step
        self._before_dues = tuple(h[2] or _NOW for h in hooks if h[0] is not None)
        self._after_dues = tuple(h[3] or _NOW for h in hooks if h[1] is not None)

    # ---- actuators ---------------------------------------------------------------------------
    def add_actuator(self, joint, kind, gains=None, effort_limit=None, error=actuators_mod.PLAIN,
                     output=actuators_mod.OUT_EFFORT):
        """The actuator of ``joint`` (a revolute, continuous or prismatic Joint of a model in this
        World): it drives the joint at every step until removed (docs/design/sim_core_api.md,
        "Actuators"). InputError when the joint cannot take one or already has one."""
        model = getattr(joint, "model", None)
        what = "add_actuator: joint '%s' of model '%s'" % (getattr(joint, "name", joint),
                                                           getattr(model, "name", "?"))
        if kind not in actuators_mod.KIND_NAMES:
            raise InputError("%s: unknown kind %r (physics.actuators: %s)"
                             % (what, kind, ", ".join(actuators_mod.KIND_NAMES.values())))
        if output not in actuators_mod.OUTPUT_NAMES:
            raise InputError("%s: unknown output %r (physics.actuators: OUT_EFFORT, OUT_VELOCITY, "
                             "OUT_POSITION)"
                             % (what, output))
        if model is None or self.models.get(model.name) is not model:
            raise InputError("%s: the joint's model is not in this World" % what)
        if joint.ode_joint is None or joint.type not in ("revolute", "continuous", "prismatic"):
            raise InputError("%s: a %s joint cannot be driven" % (what, joint.type))
        if joint.actuator is not None:
            raise InputError("%s already has an actuator (%r): remove it first, or change its kind"
                             % (what, joint.actuator))
        record = self._backend.new_actuator(joint, kind)
        a = actuators_mod.Actuator(self, self._backend, joint, kind, record)
        a.error = error
        if gains is not None:
            a.gains = gains
        a.effort_limit = effort_limit
        a.output = output
        if kind == actuators_mod.MOTOR:
            record.motor_vel = joint.velocity
        joint.bind_actuator(a)
        self._actuators.append(a)
        self._backend.actuators_changed(self._actuators)
        return a

    def remove_actuator(self, actuator):
        """The joint is free again (no effort from the actuator from the next step on; an actuator
        that drove the ODE motor gives the joint its own motor back)."""
        if actuator not in self._actuators:
            raise InputError("remove_actuator: %r is not an actuator of this World" % (actuator,))
        self._actuators.remove(actuator)
        joint = actuator.joint
        if joint.actuator is actuator:
            joint.bind_actuator(None)
            joint.effort = 0.0
            if actuator.drives_motor:
                joint.release_motor()
        self._backend.actuators_changed(self._actuators)

    @property
    def actuators(self):
        """Every actuator of the World, in the order they run."""
        return tuple(self._actuators)

    def add_model_actuator(self, model, kind):
        """A model actuator of ``model`` (a model in this World whose canonical link moves): it
        drives the whole model at every step, before the joint actuators, until removed
        (physics.actuators: PLANAR_VELOCITY). InputError when the model cannot take one."""
        what = "add_model_actuator: model '%s'" % getattr(model, "name", model)
        if kind not in actuators_mod.MODEL_KIND_NAMES:
            raise InputError("%s: unknown kind %r (physics.actuators: PLANAR_VELOCITY)" % (what, kind))
        if model is None or self.models.get(getattr(model, "name", None)) is not model:
            raise InputError("%s: the model is not in this World" % what)
        if model.canonical_link.body is None:
            raise InputError("%s: its canonical link '%s' is static (fixed to the world): nothing to move"
                             % (what, model.canonical_link.name))
        if any(a.model is model for a in self._model_actuators):
            raise InputError("%s already has a model actuator: remove it first" % what)
        a = actuators_mod.ModelActuator(self, model, kind, self._backend.new_model_actuator(model, kind))
        self._model_actuators.append(a)
        self._backend.model_actuators_changed(self._model_actuators)
        return a

    def remove_model_actuator(self, actuator):
        """The model is free again from the next step on (a removed model's go with it)."""
        if actuator not in self._model_actuators:
            return
        self._model_actuators.remove(actuator)
        self._backend.model_actuators_changed(self._model_actuators)

    @property
    def model_actuators(self):
        """Every model actuator of the World, in the order they run."""
        return tuple(self._model_actuators)

    def weld(self, link, to=None):
        """(addition) Hold ``link`` where it is relative to the link ``to`` (None: the world) with
        an ODE fixed joint until ``release()`` of the returned :class:`Weld` (a grasp that
        attaches an object to a palm). InputError when ``link`` cannot move."""
        if link.body is None:
            raise InputError("weld: link '%s' of model '%s' is static: nothing to hold"
                             % (link.name, link.model.name))
        return Weld(self._p.ode_world, link, to)

    def set_mimic(self, joint, master=None, multiplier=1.0, offset=0.0):
        """(addition) Couple ``joint`` to ``master`` (a joint of the same model) as a URDF
        <mimic> couples it: position = multiplier * master + offset, held at every step by the
        World's mimic coupling (natively between hooks); ``master`` None releases the joint.
        InputError for joints that cannot be coupled."""
        model = getattr(joint, "model", None)
        what = "set_mimic: joint '%s' of model '%s'" % (getattr(joint, "name", joint),
                                                        getattr(model, "name", "?"))
        if model is None or self.models.get(model.name) is not model:
            raise InputError("%s: the joint's model is not in this World" % what)
        if master is None:
            joint.set_mimic(None)
        else:
            if getattr(master, "model", None) is not model:
                raise InputError("%s: the master joint '%s' is not a joint of the same model"
                                 % (what, getattr(master, "name", master)))
            for j in (joint, master):
                if j.ode_joint is None or j.type not in ("revolute", "continuous", "prismatic"):
                    raise InputError("%s: joint '%s' is %s; only revolute, continuous and prismatic "
                                     "joints can be coupled" % (what, j.name, j.type))
            if joint is master:
                raise InputError("%s: a joint cannot mimic itself" % what)
            m, o = float(multiplier), float(offset)
            if not (math.isfinite(m) and math.isfinite(o)):
                raise InputError("%s: multiplier %r and offset %r must be finite"
                                 % (what, multiplier, offset))
            joint.set_mimic((master.name, m, o))
        self._rebuild_caches()

    # ---- models ------------------------------------------------------------------------------
    def warn_once(self, key, message):
        """(physics side) log ``message`` once per ``key`` for this World."""
        warn_once(self._p.warned, key, message)

    _warn_once = warn_once

    def space(self, dynamic):
        """(builder) the PyODE space of the moving (``dynamic``) or the static geoms."""
        return self._p.dyn_space if dynamic else self._p.static_space

    def destroy_model_objects(self, model):
        """(builder) a model whose building failed: drop every ODE object it made."""
        self._destroy_model_objects(model)

    def abandon(self):
        """Leave the ODE objects to the operating system at exit instead of freeing them (a thread
        that cannot be stopped may still be inside a step: freeing ODE under it would abort the
        process). The World cannot be used afterwards."""
        self._finalizer.detach()

    def _check_new_name(self, name):
        if not isinstance(name, str) or not name.strip():
            raise ModelError("a model name must be a non-empty string, got %r" % (name,))
        if name in self.models:
            raise ModelError("a model named '%s' already exists: delete it first or choose another "
                             "name" % name)

    def add_urdf(self, name, urdf_xml, pose=IDENTITY_POSE, joint_positions=None, robot_namespace=""):
        """Spawn a URDF model. Raises ModelError (the world is then unchanged)."""
        self._check_new_name(name)
        try:
            pose = check_pose(pose if pose is not None else IDENTITY_POSE,
                              "model '%s' spawn pose" % name)
        except ValueError as e:
            raise ModelError(str(e))
        desc = read_urdf(name, urdf_xml, self._warn_once)
        return self._spawn(desc, pose, joint_positions, robot_namespace or "")

    def add_sdf(self, sdf_xml, name=None, pose=None):
        """Spawn every model of an SDF <world> (or one <model>); returns the list of Models.
        ``pose`` is the frame the file is placed in: a model's own ``<pose>`` is given in it (as
        gazebo_ros's spawn composes the initial pose with the model's pose), so None or the
        identity leaves every model where its file puts it. All-or-nothing: on any ModelError no
        model of the file stays in the world."""
        from .sdf_reader import read_sdf
        descs, settings = read_sdf(sdf_xml, name, self._warn_once, self._resolver)
        seen = set()
        for d in descs:
            self._check_new_name(d.name)
            if d.name in seen:
                raise ModelError("the SDF defines two models named '%s'" % d.name)
            seen.add(d.name)
        if pose is not None:
            try:
                pose = check_pose(pose, "SDF spawn pose")
            except ValueError as e:
                raise ModelError(str(e))
        made = []
        try:
            for d in descs:
                p = d.pose or IDENTITY_POSE
                if pose is not None:
                    p = pose_mul(pose, p)
                made.append(self._spawn(d, p, None, ""))
            if settings:
                # a <world>'s <gravity> and <physics> apply to this World, as when Gazebo loads it,
                # once every model of it is in (a refused world changes nothing); the reader has
                # checked time step and gravity, set_physics_params checks all before it applies
                if settings.get("params"):
                    try:
                        self.set_physics_params(**settings["params"])
                    except ValueError as e:
                        raise ModelError("SDF <world><physics><ode>: %s" % e)
                if "time_step" in settings:
                    self.time_step = settings["time_step"]
                if "gravity" in settings:
                    self.gravity = settings["gravity"]
        except ModelError:
            for m in made:
                self.remove_model(m.name)
            raise
        return made

    def _spawn(self, desc, pose, joint_positions, robot_namespace):
        targets = {}
        if joint_positions:
            for jn, q in dict(joint_positions).items():
                jd = desc.joints.get(jn)
                if jd is None:
                    raise ModelError("model '%s': initial position for unknown joint '%s' (joints: %s)"
                                     % (desc.name, jn, ", ".join(desc.joints) or "none"))
                if jd.type not in ("revolute", "continuous", "prismatic"):
                    raise ModelError("model '%s': joint '%s' is %s and takes no initial position"
                                     % (desc.name, jn, jd.type))
                try:
                    q = float(q)
                except (TypeError, ValueError):
                    q = float("nan")
                if not math.isfinite(q):
                    raise ModelError("model '%s': initial position of joint '%s' is not a finite "
                                     "number: %r" % (desc.name, jn, joint_positions[jn]))
                if abs(q) > limits.JOINT_POSITION_LIMIT:
                    raise ModelError("model '%s': initial position %g of joint '%s' is beyond %g "
                                     "(limits: docs/simulator.md)"
                                     % (desc.name, q, jn, limits.JOINT_POSITION_LIMIT))
                if jd.lower is not None and jd.upper is not None:
                    q = min(max(q, jd.lower), jd.upper)  # as set_model_configuration: to the limit
                targets[jn] = q
        meshes = self._prepare_meshes(desc)
        model = build_model(self, desc, pose, robot_namespace, meshes)
        model.spawn_pose = pose
        try:
            entry = self._entry(model)
            self._finalize_model(model, entry, desc)
            if targets:
                model.apply_configuration(targets)
        except Exception:
            self._destroy_model_objects(model)
            raise
        self.models[model.name] = model
        self._rebuild_caches()
        entry.spawn_state = model.capture_state()
        # ODE renormalises quaternions on every set (not idempotent to the last bit): restore the
        # captured state once so that the live state is exactly what reset() will produce
        model.restore_state(entry.spawn_state, zero_velocity=False)
        self._set_snapshot(entry, entry.spawn_state)
        self._check_spawn_overlap(model)
        LOG.info("spawned model '%s': %d links, %d joints, %d bodies%s", model.name, len(model.links),
                 len(model.joints), len(model.bodies), " (static)" if model.is_static else "")
        return model

    def _entry(self, model):
        e = self._p.entries.get(model)
        if e is None:
            e = self._p.entries[model] = _ModelEntry(model)
        return e

    def _finalize_model(self, model, entry, desc):
        # collision filtering: links of one model never collide unless selfCollide; a model with
        # several bodies and no selfCollide gets a category bit so that ODE itself drops its
        # internal pairs before any Python callback (62 slots; beyond, Python filters)
        if desc.self_collide:
            for ln in model.links.values():
                ln.self_collide = True
        any_self = any(ln.self_collide for ln in model.links.values())
        slot = 0
        if len(model.groups) > 1 and not any_self:
            for s in range(1, 62):
                if s not in self._used_slots:
                    slot = s
                    break
        entry.slot = slot
        if slot:
            self._used_slots.add(slot)
            cat, col = 1 << slot, _ALL_BITS & ~(1 << slot)
        else:
            cat, col = _ALL_BITS, _ALL_BITS
        for geom in model.geoms:
            info = self._p.geom_info[geom]
            info.self_collide = info.link.self_collide
            geom.setCategoryBits(cat)
            geom.setCollideBits(col)
            self._backend.update_geom(info)
        adj = set()
        for j in model.joints_in_order:
            if j.type in ("fixed", "floating"):
                continue  # floating: no constraint, the links are independent bodies
            cg = model.links[j.child].group.index
            if j.parent == "world":
                pg = model.canonical_link.group.index if model.canonical_link.body is None else -1
            else:
                pg = model.links[j.parent].group.index
            adj.add((pg, cg))
            adj.add((cg, pg))
        entry.adjacent = frozenset(adj)
        self._apply_auto_disable(model)

    def remove_model(self, name):
        model = self.models.get(name)
        if model is None:
            raise ModelError("no model named '%s' (models: %s)" % (name, ", ".join(self.models) or "none"))
        del self.models[name]
        slot = self._entry(model).slot
        self._frozen.pop(name, None)
        self._guard_log.pop(name, None)
        self._p.warned = set(k for k in self._p.warned if not k.startswith("planar:%s:" % name))
        self._destroy_model_objects(model)
        self._wake_all()  # whatever rested on it must fall
        self._used_slots.discard(slot)
        self._rebuild_caches()
        LOG.info("removed model '%s'", name)

    def _destroy_model_objects(self, model):
        for w, m in self._watches:
            if m is model:
                w.close()
        self._watches = [(w, m) for w, m in self._watches if not w.closed]
        if any(a.model is model for a in self._model_actuators):
            self._model_actuators = [a for a in self._model_actuators if a.model is not model]
            self._backend.model_actuators_changed(self._model_actuators)
        gone = [a for a in self._actuators if a.joint.model is model]
        if gone:
            self._actuators = [a for a in self._actuators if a.joint.model is not model]
            for a in gone:
                a.joint.bind_actuator(None)
            self._backend.actuators_changed(self._actuators)
        _destroy_objects(model, self._p.geom_info, self._backend, self._wrench_links)
        self._effort_joints = [j for j in self._effort_joints if j.model is not model]
        self._last_effort_joints = [j for j in self._last_effort_joints if j.model is not model]
        self._p.contact_group.empty()
        entry = self._p.entries.pop(model, None)
        if entry is not None:
            self._backend.forget_model(entry)

    def _rebuild_caches(self):
        # models, links or bodies came or went: caches kept outside the World (the node's
        # serialised states) compare this number
        self.layout_version += 1
        self._adopt_native_snapshot()       # before the backend's arrays change
        ms = list(self.models.values())
        self._p.dynamic_models = [m for m in ms if m.bodies and m.name not in self._frozen]
        joints = [j for m in ms for j in m.joints_in_order if j.ode_joint is not None]
        # explicit damping, bounded by what the step can take stably: (joint, coefficient)
        self._p.damped = [(j, min(j.damping, j.child_inertia / self._p.dt)) for j in joints
                          if j.damping > 0.0]
        self._p.mimics = [(j, m.joints[j.mimic[0]]) for m in ms for j in m.joints_in_order
                          if j.mimic is not None and j.ode_joint is not None]
        self._p.unwrap = [j for j in joints if j.tracks_turns]
        self._p.soft = [j for j in joints if j.has_soft_limits]
        self._anti_gravity = [g for m in ms for g in m.dynamic_groups if g.anti_gravity]
        self._backend.rebuild(list(self.models.values()))

    def register_geom(self, geom, model, link, collision, surface, body):
        """(builder) ``geom`` of ``link`` of ``model`` (its <collision> named ``collision``):
        collision tables and the backend."""
        model.add_geom(geom)
        info = _GeomInfo(geom, self._entry(model), link, collision, surface, body)
        self._p.geom_info[geom] = info
        self._backend.register_geom(info)

    # ---- physics-side interface (called by Model, Link, Joint and the builder) ----------------
    @property
    def ode_world(self):
        """The PyODE world (for physics-side helpers that add their own ODE joints)."""
        return self._p.ode_world

    def queue_effort(self, joint):
        """``joint`` has an effort command for the next step."""
        self._effort_joints.append(joint)

    def queue_wrench(self, link):
        """``link`` has wrenches to apply from the next step on."""
        self._wrench_links.add(link)

    def place_static_geom(self, geom, pose):
        if isinstance(geom, ode.GeomPlane):
            n = geom.attribs.get("local_normal")
            if n is not None:
                nw = quat_rotate(pose[1], n)
                geom.setParams(nw, dot(nw, pose[0]))
            return
        geom.setPosition(pose[0])
        geom.setQuaternion(to_ode_quat(pose[1]))

    def make_plane(self, normal, pose):
        """(builder) a static plane geom with ``normal`` in the frame ``pose``."""
        n = normalized(normal)
        nw = quat_rotate(pose[1], n)
        geom = ode.GeomPlane(self._p.static_space, nw, dot(nw, pose[0]))
        geom.attribs["local_normal"] = n
        return geom

    def group_gravity_changed(self, group):
        body = group.body
        if body is None:
            return
        # gravity acts on mass: a massless link (a tool frame welded on) has no say in the body's
        # mode, else its default "on" would make a body of gravity-off links a mixed one
        flags = [ln.gravity_enabled for ln in group.links if ln.mass > 0] or \
            [ln.gravity_enabled for ln in group.links]
        if all(flags):
            body.setGravityMode(True)
            group.anti_gravity = ()
        elif not any(flags):
            body.setGravityMode(False)
            group.anti_gravity = ()
        else:
            body.setGravityMode(True)
            anti = []
            for ln in group.links:
                if not ln.gravity_enabled and ln.mass > 0:
                    anti.append((ln.mass, pose_mul(ln.body_offset, ln.inertial_origin)[0]))
            group.anti_gravity = tuple(anti)
        body.enable()
        if group.model.name in self.models:
            self._rebuild_caches()

    # ---- meshes ------------------------------------------------------------------------------
    def _resolve(self, uri):
        if self._resolver is not None and (uri.startswith("package://") or uri.startswith("file://")
                                           or uri.startswith("model://")):
            path = self._resolver(uri)
            if not path:
                raise meshlib.MeshError("the resource resolver returned nothing")
            return path
        return meshlib.default_resolver(uri, self._rospack)

    #: while a model's meshes are prepared: the rospkg.RosPack that resolves its package:// URIs
    #: (one crawl of ROS_PACKAGE_PATH for all of them); None otherwise (a new one per URI)
    _rospack = None

    def _offline_meshes(self, desc):
        """A ``model://`` mesh found nowhere on this machine (Gazebo would download it from its
        online model database) is dropped from its link with one warning naming the URI and where
        it looked, as Gazebo goes on without it; the rest of the model loads. Visual meshes with a
        ``model://`` URI that is found become ``file://`` paths, so that RViz can load them. A
        moving link left without any collision (turtlebot3_house's mailbox) would fall through
        the world: it stays where it stands (static), and the warning says so."""
        for ld in desc.links.values():
            had = len(ld.collisions)
            for kind, geoms in (("collision", ld.collisions), ("visual", ld.visuals)):
                for gd in list(geoms):
                    if gd.kind != "mesh" or not (gd.uri or "").startswith("model://"):
                        continue
                    try:
                        path = self._resolve(gd.uri)
                    except meshlib.ResourceNotFound as e:
                        geoms.remove(gd)
                        self._warn_once("mesh-offline:%s:%s" % (desc.name, gd.uri),
                                        "model '%s' link '%s': %s mesh skipped: %s"
                                        % (desc.name, ld.name, kind, e))
                        continue
                    except Exception:   # reported with the link by _prepare_meshes
                        continue
                    if kind == "visual" and path:
                        gd.uri = "file://" + os.path.abspath(path)
            if had and not ld.collisions and not desc.link_static(ld):
                ld.static = True
                self._warn_once("mesh-offline-held:%s:%s" % (desc.name, ld.name),
                                "model '%s' link '%s': no collision is left; the link is held where it "
                                "stands (static) instead of falling through the world"
                                % (desc.name, ld.name))

    def _mesh_file(self, uri):
        """The existing file a mesh URI names, or None."""
        try:
            path = self._resolve(uri)
        except Exception:   # noqa: B902 - any resolver failure means: not here
            return None
        return path if path and os.path.isfile(path) else None

    def _unbuilt_collision_meshes(self, desc):
        """A collision mesh whose file is missing while the same link's visual mesh exists (a mesh
        its package makes at build time: katana_description's convex decompositions come from
        convex_decomposition and ivcon, which Debian lacks) collides as that visual mesh; one
        warning per model lists them. Gazebo would refuse the model; this keeps a robot checked out
        from source usable."""
        swapped = []
        for ld in desc.links.values():
            visual = next((v for v in ld.visuals if v.kind == "mesh" and v.uri
                           and self._mesh_file(v.uri)), None)
            if visual is None:
                continue
            for i, gd in enumerate(ld.collisions):
                if (gd.kind != "mesh" or not gd.uri or gd.uri.startswith("model://")
                        or self._mesh_file(gd.uri)):
                    continue
                ld.collisions[i] = GeometryDesc("mesh", visual.size, visual.origin, visual.uri, gd.name,
                                                gd.surface)
                swapped.append("%s ('%s' -> '%s')" % (ld.name, gd.uri, visual.uri))
        if swapped:
            self._warn_once("mesh-unbuilt:%s" % desc.name,
                            "model '%s': %d collision mesh file%s do%s not exist (files a package makes "
                            "when it is built?); those links collide as their visual meshes instead: %s"
                            % (desc.name, len(swapped), "s" if len(swapped) > 1 else "",
                               "" if len(swapped) > 1 else "es", "; ".join(swapped)))

    def _missing_visual_meshes(self, desc):
        """A visual mesh whose file is not on this machine (a package:// or file:// URI naming
        no file; model:// ones are _offline_meshes') is dropped from its link with one warning per
        model listing them: Gazebo's client draws nothing there and says so once, where RViz (the
        camera renderer's scene) would report it again at every update of the scene markers."""
        gone = []
        for ld in desc.links.values():
            for gd in list(ld.visuals):
                if gd.kind == "mesh" and gd.uri and not gd.uri.startswith("model://") and \
                        self._mesh_file(gd.uri) is None:
                    ld.visuals.remove(gd)
                    gone.append("%s ('%s')" % (ld.name, gd.uri))
        if gone:
            self._warn_once("mesh-visual-missing:%s" % desc.name,
                            "model '%s': %d visual mesh file%s not found, not drawn (as Gazebo's "
                            "client draws nothing there): %s"
                            % (desc.name, len(gone), "s" if len(gone) > 1 else "", "; ".join(gone)))

    def _prepare_meshes(self, desc):
        """Resolve and load every collision mesh of ``desc`` before any ODE object is made."""
        try:
            import rospkg
            self._rospack = rospkg.RosPack()    # it crawls at its first lookup
        except ImportError:
            self._rospack = None                # default_resolver says so at a package:// URI
        try:
            return self._prepare_mesh_files(desc)
        finally:
            self._rospack = None

    def _prepare_mesh_files(self, desc):
        self._offline_meshes(desc)
        self._unbuilt_collision_meshes(desc)
        self._missing_visual_meshes(desc)
        out = {}
        for ld in desc.links.values():
            for gd in ld.collisions:
                if gd.kind != "mesh":
                    continue
                where = "model '%s' link '%s'" % (desc.name, ld.name)
                try:
                    path = self._resolve(gd.uri)
                except meshlib.MeshError as e:
                    raise ModelError("%s: cannot resolve mesh URI '%s': %s" % (where, gd.uri, e))
                except Exception as e:  # a user resolver may raise anything: report it
                    raise ModelError("%s: cannot resolve mesh URI '%s': %s: %s"
                                     % (where, gd.uri, type(e).__name__, e))
                if not os.path.isfile(path):
                    raise ModelError("%s: mesh file for '%s' not found (looked at '%s')"
                                     % (where, gd.uri, path))
                try:
                    st = os.stat(path)
                    key = (path, st.st_mtime_ns, st.st_size)
                    mesh = self._mesh_cache.get(key)
                    if mesh is None:
                        mesh = meshlib.load_mesh(path)
                        self._mesh_cache[key] = mesh
                except meshlib.MeshError as e:
                    raise ModelError("%s: mesh '%s': %s" % (where, gd.uri, e))
                verts, tris = mesh
                verts = meshlib.scaled(verts, gd.size)
                tris = meshlib.flip_if_mirrored(tris, gd.size)
                out[id(gd)] = (verts, tris)
        return out

    def make_mesh_geom(self, mesh, dynamic, what):
        """A triangle-mesh geom (native) or, on the pure-Python path (PyODE on Debian has no
        trimesh), its bounding box. Returns (geom, pose of the geom in the mesh frame)."""
        return self._backend.make_mesh_geom(mesh, dynamic, what)

    # ---- stepping ----------------------------------------------------------------------------
    def step(self, n=1):
        """n steps: for each, before-hooks(t, dt), model and joint actuators and forces, collide +
        ODE quickStep, guard, after-hooks(t + dt, dt); on the native backend the steps at which no
        hook is due run in C, in stretches up to the next due hook (docs/physics.md, "One step")."""
        n = int(n)
        if n < 0:
            raise InputError("step(n): n must not be negative")
        done = 0
        while done < n:
            done += self._advance(n - done)

    def advance(self, n):
        """(addition) At most ``n`` steps (n >= 1), as step(n) makes them, ending early where a
        native stretch ends for Python (a hook's due time, a wake): returns the steps made. A
        simulation loop that takes its passes this way lets its passes fall on the hooks' stops
        instead of adding stops of its own (a pass of 10 steps on another phase than a 100 Hz
        controller's updates stopped the World twice in every 10 ms)."""
        n = int(n)
        if n < 1:
            raise InputError("advance(n): n must be at least 1")
        done = 0
        while done < n:
            stretches = self.native_steps + self.hooked_steps
            k = self._advance(n - done)
            done += k
            if self.native_steps + self.hooked_steps != stretches:
                # a native stretch ended for Python: the pass ends there, unless a hook is due at
                # every step (this stretch and the one before made one step each), where a pass
                # per step would only add the loop's own work; steps in Python go on to n too
                every_step = k == 1 and self._last_stretch == 1
                self._last_stretch = k
                if not every_step:
                    break
        return done

    def _advance(self, n):
        """At most ``n`` steps: a native stretch up to the first step at which a hook is due or
        the World needs Python. At a step whose before-hooks are due they run here and the
        step's physics is the first of the stretch (unless the hooks gave the World a reason for
        Python: then that step is made in Python). Returns the steps made."""
        t = self.time
        if not (self._backend.native and self._stretch_ok()):
            self._step_once()
            return 1
        backend = self._backend
        backend.clear_wake()        # before the due times: a wake after this ends the stretch
        due = earliest_due(self._before_dues)
        before = due - DUE_MARGIN
        hooked = stops_at(t, due)
        if hooked:
            self.stops += 1
            dt = self._p.dt
            for h in self._before:
                h(t, dt)
            if not self._stretch_ok():
                self._step_once(hooked=True)
                return 1
            backend.clear_wake()    # what the hooks took needs no wake; what came since does
            # the step at t is made whatever the hooks say now; the stretch goes on to their next due time
            before = max(earliest_due(self._before_dues) - DUE_MARGIN, t + 0.5 * dt)
        after = earliest_due(self._after_dues) - DUE_MARGIN
        efforts = self._take_efforts()
        r = backend.run(n, t, self.iterations, before, after, efforts)
        if r is not None:
            if hooked:
                self.hooked_steps += 1
                self.native_steps -= 1
            self._after_stretch(r, efforts[0])
            return r.steps
        self._step_once(hooked=hooked, efforts=efforts)     # the efforts are this step's
        return 1

    def _stretch_ok(self):
        """The World's own reasons to step in Python: wrenches, partial gravity, a frozen model
        (held in Python), a mimic or soft-limit joint the C loop cannot drive."""
        return not (self._wrench_links or self._anti_gravity or self._frozen) and self._backend.stretch_ok

    def _after_stretch(self, r, joints):
        """``joints``: those whose queued efforts the stretch's first step applied."""
        self.native_steps += r.steps
        self.time, self.iterations = r.time, r.iterations
        self._ncontacts = r.ncontacts
        if r.steps == 1:
            self._last_effort_joints = joints
        else:                                   # given for the first step only
            for j in joints:
                j.effort = 0.0
        if r.guard:
            self._guard()
            if self._frozen:
                self._hold_frozen()
        if r.after:             # the last step's after-hooks are due
            self.stops += 1
            t, dt = self.time, self._p.dt
            for h in self._after:
                h(t, dt)

    def _step_once(self, hooked=False, efforts=None):
        """One step in Python; ``hooked``: its before-hooks have run already (and were counted);
        ``efforts``: the step's queued efforts, taken already (_take_efforts)."""
        if not hooked:
            self.stops += 1
        dt = self._p.dt
        t = self.time
        if not hooked:
            for h in self._before:
                h(t, dt)
        self._apply_forces(t, dt, efforts)
        self._ncontacts = self._backend.step(dt)
        self.iterations += 1
        self.time = next_time(t, dt)
        self._backend.track_turns(self._p.unwrap)
        self._guard()
        if self._frozen:
            self._hold_frozen()
        for h in self._after:
            h(self.time, dt)

    def _take_efforts(self):
        """A step's queued efforts (set_effort, add_effort), taken: a joint with an actuator hands
        its raw sum to the actuator (added before the joint's clamp in the actuator's step); the
        others' clamped efforts are returned as (joints, efforts), for the step to apply after the
        model actuators, and reported by the joints from now on; those of the step before that
        are not given again report 0."""
        queued = self._effort_joints
        if queued:
            self._effort_joints = []
            joints = [j for j in queued if j.actuator is None]
            if len(joints) < len(queued):
                for j in queued:
                    a = j.actuator
                    if a is not None:
                        a.add_extra(j.take_command())
        else:
            joints = ()
        last = self._last_effort_joints
        if last and last != joints:     # (the same joints again: each reports its new effort)
            for j in last:
                j.effort = 0.0
        self._last_effort_joints = ()
        return joints, [j.take_effort() for j in joints] if joints else ()

    def _apply_forces(self, t, dt, efforts=None):
        if self._model_actuators:
            self._backend.apply_model_actuators(self._model_actuators)
        joints, values = self._take_efforts() if efforts is None else efforts
        for j, f in zip(joints, values):
            j.add_raw_effort(f)
        self._last_effort_joints = joints
        if self._actuators:
            self._backend.apply_actuators(self._actuators, t, dt)
        self._backend.apply_damping()
        for j, m in self._p.mimics:
            j.drive_mimic(m, dt)
        for j in self._p.soft:
            j.update_soft_limits()
        if self._wrench_links:
            for ln in list(self._wrench_links):
                if not ln.apply_wrenches(dt):
                    self._wrench_links.discard(ln)
        if self._anti_gravity:
            g = self._p.gravity
            for grp in self._anti_gravity:
                b = grp.body
                for m, rel in grp.anti_gravity:
                    b.addForceAtRelPos((-m * g[0], -m * g[1], -m * g[2]), rel)

    # ---- guard -------------------------------------------------------------------------------
    def _guard(self):
        """The blow-up guard after a step: models whose bodies run away (or explode in contacts)
        go back to their last sane state; every snapshot_interval steps the others are saved."""
        flagged = self._backend.find_blowups()
        if flagged:
            self._adopt_native_snapshot()
        for m, g, reason in flagged:
            self._restore_after_blowup(m, g.root.name, reason)
        if self.iterations % int(self._p.params["snapshot_interval"]) == 0:
            bad = set(id(f[0]) for f in flagged)
            for m in self._p.dynamic_models:
                if id(m) not in bad:
                    self._set_snapshot(self._p.entries[m], m.capture_state())

    def _set_snapshot(self, entry, state):
        entry.snapshot_state = state
        entry.snapshot_iter = self.iterations

    def _adopt_native_snapshot(self):
        """The C loop takes the guard's snapshots at the steps on its interval at which nothing
        was flagged, without stopping for Python (mr_run_steps); its last one becomes the snapshot
        of each model it is newer for, before a restoration reads one and before the backend's
        arrays change."""
        k = self._backend.snapshot_iteration
        if k < 0:
            return
        body, joint = self._backend.snapshot_readers()
        entries = self._p.entries
        for m in self._p.dynamic_models:
            e = entries.get(m)
            if e is not None and e.snapshot_iter < k:
                e.snapshot_state = m.capture_state(body, joint)
                e.snapshot_iter = k

    def _restore_after_blowup(self, model, link, reason):
        ev = GuardEvent(model.name, link, reason, self.time)
        self._events.append(ev)
        # back off: one message per model per simulated second, with the count of the others;
        # a model restored GUARD_STREAK_LIMIT times without a second of peace is frozen (held
        # still, the rest of the world goes on) instead of looping for ever
        g = self._guard_log.get(model.name)
        t = self.time
        if g is None or not 0.0 <= t - g[0] < 1.0:
            more = "" if g is None or not g[1] else " (%d more restorations in the last second)" % g[1]
            LOG.error("blow-up guard: model '%s' link '%s': %s at t=%.4f s; restored to its last sane "
                      "state (zero velocity, wrenches cleared)%s", model.name, link, reason, t, more)
            g = [t, 0, g[2] if g is not None and 0.0 <= t - g[3] < 1.0 else 0, t]
            self._guard_log[model.name] = g
        else:
            g[1] += 1
        g[2] = g[2] + 1 if 0.0 <= t - g[3] < 1.0 else 1
        g[3] = t
        entry = self._p.entries[model]
        state = entry.snapshot_state or entry.spawn_state
        model.restore_state(state, zero_velocity=True)
        self._backend.forget_anchors()
        if not model.state_finite():
            state = entry.spawn_state
            model.restore_state(state, zero_velocity=True)
        if g[2] >= GUARD_STREAK_LIMIT:
            g[2] = 0
            self._freeze(model, state, link, reason)

    # ---- frozen models (the guard's last resort) ---------------------------------------------
    def _freeze(self, model, state, link, reason):
        """Hold ``model`` still in ``state`` (its last sane state): its bodies become kinematic
        (infinite mass, zero velocity: others collide with it as with a static object, its joints
        and efforts move nothing); the rest of the world goes on. set_model_state /
        set_model_configuration / set_link_state, reset or delete release it."""
        msg = ("blow-up guard: model '%s' was restored %d times in a row (last: link '%s', %s): "
               "the model is FROZEN, the rest of the world goes on. Fix the model (masses, joint "
               "limits, mimic offsets) or what commands it (gains, efforts); set_model_state, "
               "set_model_configuration, reset_simulation/reset_world or delete_model release it"
               % (model.name, GUARD_STREAK_LIMIT, link, reason))
        LOG.error("%s", msg)
        self._frozen[model.name] = (model, state, msg)
        self._events.append(GuardEvent(model.name, link, FROZEN_REASON, self.time))
        self._rebuild_caches()  # out of the guard's and the snapshots' lists
        self._hold(model, state)

    @staticmethod
    def _hold(model, state):
        model.restore_state(state, zero_velocity=True)
        for b in model.bodies:
            b.setForce((0.0, 0.0, 0.0))
            b.setTorque((0.0, 0.0, 0.0))
            if odelib.AVAILABLE:
                odelib.LIB.dBodySetKinematic(odelib.raw_pointer(b))
            else:
                b.disable()

    def _hold_frozen(self):
        for model, state, _msg in self._frozen.values():
            moved = False
            for b in model.bodies:
                # a kinematic body keeps its zero velocity; a disabled one (no ctypes access to
                # libode) is woken by contacts: then put it back
                moved = moved or b.isEnabled() != bool(odelib.AVAILABLE)
                b.setForce((0.0, 0.0, 0.0))  # efforts commanded meanwhile must not pile up
                b.setTorque((0.0, 0.0, 0.0))
            if moved:
                self._hold(model, state)

    @property
    def frozen_models(self):
        """{model name: message} of the models the guard froze (addition)."""
        return OrderedDict((n, f[2]) for n, f in self._frozen.items())

    def unfreeze(self, name):
        """Release a model the guard froze (addition); False if it was not frozen. Its bodies
        wake with zero velocity; the guard's count starts again."""
        f = self._frozen.pop(name, None)
        if f is None:
            return False
        self._guard_log.pop(name, None)
        model = f[0]
        for b in model.bodies:
            if odelib.AVAILABLE:
                odelib.LIB.dBodySetDynamic(odelib.raw_pointer(b))  # its mass comes back
            b.enable()
        entry = self._p.entries.get(model)
        if entry is not None:
            entry.ncontacts = 0
            self._set_snapshot(entry, model.capture_state())
        self._rebuild_caches()
        LOG.warning("model '%s' released from the blow-up guard's freeze", name)
        return True

    def contacts(self):
        """The contact points made in the last step (addition to the contract): a list of
        ContactPoint, at most max_contacts per geom pair, depth as the collider reported it."""
        out = []
        for i1, i2, pos, normal, depth, (f1, t1, f2, t2) in self._backend.contacts():
            # a static side has no body for ODE to report on: it takes the reaction of the other
            # side's force, with its torque about the static link's frame origin
            if i1.body is None:
                f1, t1 = _reaction(f2, pos, i1.link)
            elif i2.body is None:
                f2, t2 = _reaction(f1, pos, i2.link)
            out.append(ContactPoint(i1.model.name, i1.link.name, i2.model.name, i2.link.name, pos, normal,
                                    depth, f1, t1, f2, t2))
        return out

    def watch_contacts(self, links):
        """(addition) A :class:`ContactWatch` on ``links`` (Links of one model of this World):
        from now on every step notes, where its contacts are made (in C on the native backend),
        each pair of collisions (one of a watched link, the other on a body of another model, or
        of its own with self-collision) that made contacts, and counts the steps in which it did;
        ``drain()`` hands out the pairs seen since the last drain (SeenContact, with those
        steps). reset() and reset_world() drop what was seen; deleting the model closes the
        watch; a model frozen by the guard keeps its watches. InputError when the links are not
        links of one model of this World."""
        links = list(links)
        if not links:
            raise InputError("watch_contacts: no link given; give the Links of one model to watch")
        model = getattr(links[0], "model", None)
        name = getattr(model, "name", None)
        for ln in links:
            if getattr(ln, "model", None) is not model or model.links.get(ln.name) is not ln:
                raise InputError("watch_contacts: %r is not a link of model '%s'; a watch takes links of "
                                 "one model" % (ln, name))
        # (a model being built is not in self.models yet; its collisions are in the tables)
        if model.removed or (self.models.get(name) is not model and self._p.entries.get(model) is None
                             and model.geoms):
            raise InputError("watch_contacts: model '%s' is not in this World" % name)
        names = frozenset(ln.name for ln in links)
        infos = [self._p.geom_info[g] for g in model.geoms if self._p.geom_info[g].link.name in names]
        watch = ContactWatch(self._backend, name, names, self._backend.new_watch(infos))
        self._watches = [(w, m) for w, m in self._watches if not w.closed] + [(watch, model)]
        return watch

    def pop_events(self):
        ev, self._events = self._events, []
        return ev

    def model_teleported(self, model):
        """``model`` was moved by hand: that is its new sane state for the guard (and a model the
        guard froze is released)."""
        if model.name in self._frozen and self._frozen[model.name][0] is model:
            self.unfreeze(model.name)
        entry = self._p.entries.get(model)
        if entry is not None:
            self._set_snapshot(entry, model.capture_state())
        if model.is_static or model.world_attached:
            self._wake_all()  # sleeping bodies resting on a moved static part must notice

    def _wake_all(self):
        for m in self._p.dynamic_models:
            m.wake()

    # ---- reset, digest -----------------------------------------------------------------------
    def reset(self):
        """reset_simulation: time and iterations to 0, every model to its spawn state."""
        self.time = 0.0
        self.iterations = 0
        self._reseed()
        self.reset_world()

    def reset_world(self):
        """reset_world: poses and velocities of every model to the spawn state; time kept."""
        self._p.contact_group.empty()
        for name in list(self._frozen):
            self.unfreeze(name)
        self._backend.drop_snapshot()       # of the time before: reset() may have sent time back
        self._backend.forget_anchors()      # where the contacts held: the bodies are elsewhere now
        self.reset_count += 1
        self._watches = [(w, m) for w, m in self._watches if not w.closed]
        for w, _m in self._watches:
            w.clear()
        for m in self.models.values():
            e = self._p.entries[m]
            m.restore_state(e.spawn_state, zero_velocity=False)
            self._set_snapshot(e, e.spawn_state)
            e.ncontacts = 0
        self._effort_joints = []
        self._last_effort_joints = []

    def state_digest(self):
        """SHA-256 (hex) over time, iterations and every body's pose and velocity."""
        h = hashlib.sha256()
        h.update(struct.pack("<dq", self.time, self.iterations))
        for m in self.models.values():
            h.update(m.name.encode("utf-8"))
            for b in m.bodies:
                h.update(struct.pack("<13d", *(b.getPosition() + b.getQuaternion() +
                                               b.getLinearVel() + b.getAngularVel())))
        return h.hexdigest()

    # ---- spawn checks ------------------------------------------------------------------------
    def _check_spawn_overlap(self, model, threshold=0.01):
        found = self._backend.overlaps(model)
        for (m1, l1, m2, l2), d in sorted(found.items()):
            if d > threshold:
                LOG.warning("spawn overlap: model '%s' link '%s' penetrates model '%s' link '%s' "
                            "by %.1f mm; contacts push them apart within a few steps (as Gazebo: the "
                            "velocity left to them is capped at maxVel)", m1, l1, m2,
                            l2, d * 1000.0)


def _destroy_objects(model, geom_info, backend, wrench_links=None):
    """Drop every ODE object of ``model`` in a safe order: geoms out of their spaces first."""
    model.close_grippers()  # their weld joints go while the ODE world still exists
    for geom in model.geoms:
        geom_info.pop(geom, None)
        if backend.remove_geom(geom):
            continue
        sp = geom.getSpace()
        if sp is not None:
            sp.remove(geom)
    if wrench_links is not None:
        for ln in model.links.values():
            wrench_links.discard(ln)
    model.release()


class Weld(object):
    """A fixed joint made by :meth:`World.weld`: ``link`` and ``to`` move as one until released."""

    def __init__(self, ode_world, link, to):
        self.link, self.to = link, to
        j = ode.FixedJoint(ode_world)
        j.attach(link.body, to.body if to is not None else None)   # a static 'to': the world
        j.setFixed()
        self._joint = j

    @property
    def active(self):
        return self._joint is not None

    def release(self):
        """End the weld (again: nothing); the link may have fallen asleep while held: wake it."""
        if self._joint is None:
            return
        self._joint.attach(None, None)
        self._joint = None
        body = None if self.link.model.removed else self.link.body
        if body is not None:
            body.enable()


def _reaction(force, point, link):
    """The force a contact at ``point`` puts on ``link`` (static) when the other side gets
    ``force``, and its torque about the link's frame origin."""
    f = (-force[0], -force[1], -force[2])
    o = link.pose[0]
    return f, cross((point[0] - o[0], point[1] - o[1], point[2] - o[2]), f)


def _teardown(models, parts, backend):
    # the ODE world, the spaces and the contact group are held here and no longer by the parts:
    # whatever still refers to the parts after the World is gone (a model kept by a user; a model's
    # links and joints refer to it, a cycle) must not hand them to the cycle collector, which would
    # free them in any order. Actuators and contact watches hold the backend weakly.
    ode_objects = (parts.ode_world, parts.static_space, parts.dyn_space, parts.contact_group)
    for m in list(models.values()):
        _destroy_objects(m, parts.geom_info, backend)
    models.clear()
    parts.geom_info.clear()
    parts.contact_group.empty()
    backend.close()
    parts.ode_world = parts.static_space = parts.dyn_space = parts.contact_group = None
    del ode_objects     # the group, the spaces, then the ODE world, after their contents


class _OrderedSet(object):
    """Insertion-ordered set (iteration order must not depend on memory addresses, or two runs
    would sum forces in different orders)."""

    def __init__(self):
        self._d = OrderedDict()

    def add(self, x):
        self._d[x] = None

    def discard(self, x):
        self._d.pop(x, None)

    def __iter__(self):
        return iter(list(self._d))

    def __len__(self):
        return len(self._d)

    def __bool__(self):
        return bool(self._d)


def _set_auto_disable(body, on):
    if odelib.AVAILABLE:  # PyODE wraps only the world-wide default
        odelib.LIB.dBodySetAutoDisableFlag(odelib.raw_pointer(body), 1 if on else 0)


#: a hook with no due function: due now, at every step
def _NOW():
    return None


def next_time(t, dt):
    """The simulated time a step of ``dt`` after ``t``, on the nanosecond grid, as Gazebo's
    common::Time (whole seconds and nanoseconds) adds its steps: 180963 steps of 1 ms summed in
    doubles come off the grid by a nanosecond (a /clock stamp then 180.963000001 s), 400000 by
    2.5 ns. mr_run_steps (C) computes the same: the nearest whole nanosecond, ties to even."""
    return round((t + dt) * 1e9) / 1e9


def earliest_due(dues):
    """The earliest of the due functions' times (None from one of them: now, -inf). The one rule of
    combining due times, for the World's hooks and for whoever gathers hooks into one."""
    due = INF
    for f in dues:
        d = f()
        if d is None:
            return -INF
        if d < due:
            due = d
    return due


__all__ = ["World", "earliest_due", "Weld", "GuardEvent", "ContactPoint", "DEFAULT_PARAMS", "FORCE_CAP",
           "SimulationError"]

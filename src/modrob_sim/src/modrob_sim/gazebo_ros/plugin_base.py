"""The one contract for everything that plugs into the /gazebo node (docs/plugins.md).

A plugin is a class derived from :class:`ModelPlugin` (a ``<plugin>`` of a model, as Gazebo's
``ModelPlugin``) or :class:`SensorPlugin` (a ``<plugin>`` inside a ``<sensor>`` block, as Gazebo's
``SensorPlugin``), registered for the Gazebo file name it stands in for::

    from modrob_sim.gazebo_ros.plugin_base import ModelPlugin
    from modrob_sim.gazebo_ros.plugins import register_plugin

    class MyPlugin(ModelPlugin):
        def load(self, model, spec, context):      # once, before the first step
            self.topic = self.param("topicName", "my_topic")
            self.pub = context.advertise(self.topic, MyMsg, queue_size=1)
        def before_step(self, t, dt): ...           # every step, before physics (controllers)
        def after_step(self, t, dt): ...            # every step, after physics (sensors)
        def reset(self): ...                        # reset_simulation / reset_world
        def shutdown(self): ...                     # model deleted or node stopping

    register_plugin("libmy_plugin.so", MyPlugin)

The node constructs the plugin with ``MyPlugin(model, spec, context)`` (the factory signature of
:func:`~modrob_sim.gazebo_ros.plugins.register_plugin`), then calls ``load(model, spec, context)``.

The one threading rule: every hook (load, before_step, after_step, reset, shutdown) runs in the
simulation loop thread, the only thread that touches the World (or, for load and shutdown, before
that thread starts / after it stopped). ROS callbacks of a plugin (subscribers, services, actions,
dynamic_reconfigure) run in rospy's threads: they store what they received (latest value or a
queue, under the plugin's own small lock) for the next hook, or hand a job to the loop with
``context.call(fn)`` and wait for its result. They never touch the World or the plugin's
simulation state directly.

This module is pure (no rospy): plugins' cores and their tests can use it without a ROS master.
"""
import math

from modrob_sim.errors import PluginError
from modrob_sim.physics.due import is_due
from modrob_sim.physics.transforms import quat_from_rpy

_UNSET = object()
INF = float("inf")


class ModelPlugin(object):
    """Base of every /gazebo plugin. Attributes set before :meth:`load`:

    model     the physics Model the plugin belongs to (modrob_sim.physics.Model)
    spec      its PluginSpec(name, filename, element, robot_namespace, link, sensor)
    element   the ``<plugin>`` xml.etree Element (Gazebo's ``_sdf``), = spec.element
    context   the PluginContext (world, namespace, rng, call, advertise, resolve ...)
    rng       the plugin's own seeded random.Random (= context.rng): deterministic per plugin,
              derived from the world's seed; re-seeded on reset_simulation before reset()

    Every hook has a no-op default: override the ones you need. A hook that raises disables the
    plugin (logged with the traceback); the simulation goes on. ``load`` raises
    :class:`~modrob_sim.errors.PluginError` (or any ModrobError) for bad configuration: the node
    then logs the message and does not load the plugin.
    """

    def __init__(self, model, spec, context):
        self.model = model
        self.spec = spec
        self.element = spec.element
        self.context = context
        self.rng = context.rng

    # ---- the hooks ---------------------------------------------------------------------------
    def load(self, model, spec, context):
        """Read the configuration, create publishers/subscribers/services. Loop thread (or the
        node's start-up before the loop runs)."""

    def before_step(self, t, dt):
        """Before every physics step at simulated time ``t`` (the step goes to ``t + dt``):
        read -> update -> write of controllers, efforts for this step."""

    def after_step(self, t, dt):
        """After every physics step; ``t`` is the new simulated time. Sensors and publishing."""

    def before_due(self):
        """The simulated time from which :meth:`before_step` next has work: the node calls it at
        the first step starting at a ``t`` with ``t + 1e-9 >= before_due()`` and steps natively
        until then (``math.inf``: not until :meth:`PluginContext.wake`). None, the default: at
        every step. Cheap, no side effects (docs/plugins.md, "Due times")."""
        return None

    def after_due(self):
        """As :meth:`before_due`, for :meth:`after_step` (the step ending at ``t``)."""
        return None

    def reset(self):
        """reset_simulation (time back to 0, rng re-seeded before this call) or reset_world."""

    def shutdown(self):
        """The model was deleted or the node stops: stop publishing, unregister, let go."""

    # ---- helpers -----------------------------------------------------------------------------
    @property
    def name(self):
        """"model 'x': plugin libfoo.so (name)" for messages."""
        label = " (%s)" % self.spec.name if self.spec.name else ""
        return "model '%s': plugin %s%s" % (self.model.name, self.spec.filename, label)

    def param(self, tag, default=_UNSET, cast=str, element=None):
        """The text of the child ``<tag>`` of the ``<plugin>`` element (or of ``element``),
        converted with ``cast`` (str, float, int or bool: "true"/"1"/"false"/"0"). Missing or
        empty: ``default``, or PluginError when no default is given. A value ``cast`` refuses (or
        a non-finite float) raises PluginError naming the model, the plugin and the tag."""
        elem = self.element if element is None else element
        node = elem.find(tag) if elem is not None else None
        text = (node.text or "").strip() if node is not None else ""
        if not text:
            if default is _UNSET:
                raise PluginError("%s: <%s> is required" % (self.name, tag))
            return default
        return convert(text, cast, "%s: <%s>" % (self.name, tag))


class SensorPlugin(ModelPlugin):
    """A ``<plugin>`` inside a ``<sensor>`` block (``<gazebo reference="link"><sensor>`` in a
    URDF, ``<link><sensor>`` in SDF). In addition to ModelPlugin's attributes:

    sensor        the ``<sensor>`` Element;  sensor_name, sensor_type (its name/type attributes)
    link          the physics Link the sensor is attached to
    sensor_pose   the ``<pose>`` of the sensor in the link frame ((x, y, z), (qx, qy, qz, qw))
    update_rate   Hz from ``<update_rate>`` (0 = every step)
    always_on, visualize   ``<always_on>``, ``<visualize>``

    :meth:`after_step` calls :meth:`sense` at ``update_rate`` in simulated time (first at t = 0+);
    override :meth:`sense`, or override after_step and use :meth:`due` yourself.
    """

    def __init__(self, model, spec, context):
        super(SensorPlugin, self).__init__(model, spec, context)
        if spec.sensor is None or not spec.link:
            raise PluginError("%s is a sensor plugin: put it inside a <sensor> block of a link "
                              "(<gazebo reference=\"link\"><sensor ...><plugin .../></sensor>)" % self.name)
        self.sensor = spec.sensor
        self.sensor_name = spec.sensor.get("name", "")
        self.sensor_type = spec.sensor.get("type", "")
        self.link = model.links.get(spec.link)
        if self.link is None:
            raise PluginError("%s: sensor '%s' refers to link '%s', which the model does not have"
                              % (self.name, self.sensor_name, spec.link))
        self.update_rate = self.param("update_rate", 0.0, float, element=self.sensor)
        if self.update_rate < 0:
            raise PluginError("%s: <update_rate> of sensor '%s' must not be negative"
                              % (self.name, self.sensor_name))
        self.always_on = self.param("always_on", True, bool, element=self.sensor)
        self.visualize = self.param("visualize", False, bool, element=self.sensor)
        self.sensor_pose = sdf_pose(self.param("pose", "", element=self.sensor),
                                    "%s: <pose> of sensor '%s'" % (self.name, self.sensor_name))
        self.gate = RateGate(self.update_rate)

    def due(self, t):
        """True when a reading is due at simulated time ``t`` (at most once per 1/update_rate)."""
        return self.gate.due(t)

    def after_step(self, t, dt):
        if self.gate.due(t):
            self.sense(t)

    def after_due(self):
        """From the update rate: the gate's next time. A subclass that overrides
        :meth:`after_step` with a decimation of its own declares its own (else: every step);
        one that overrides neither after_step nor :meth:`sense` has no step work."""
        cls = type(self)
        if cls.after_step is not SensorPlugin.after_step:
            return None
        if cls.sense is SensorPlugin.sense:
            return INF
        return self.gate.next_time

    def sense(self, t):
        """Take a reading at simulated time ``t`` and publish it (loop thread)."""

    def reset(self):
        """Subclasses that override reset call ``super().reset()`` (restarts the rate gate)."""
        self.gate.reset()


class RateGate(object):
    """Decimates a per-step hook to ``rate`` Hz of simulated time; 0 = every call. Times are the
    simulated ones passed to the hooks, never the wall clock."""

    def __init__(self, rate):
        rate = float(rate)
        if not (rate >= 0 and math.isfinite(rate)):
            raise PluginError("an update rate must be a finite number >= 0, got %r" % rate)
        self.period = 1.0 / rate if rate > 0 else 0.0
        self._next = None

    def due(self, t):
        if self.period <= 0.0:
            return True
        if self._next is None or is_due(t, self._next):
            # next slot on the period grid after t: a late call does not make a burst
            nxt = (self._next if self._next is not None else t) + self.period
            if nxt <= t + 1e-9:
                nxt = t + self.period
            self._next = nxt
            return True
        return False

    @property
    def next_time(self):
        """The simulated time from which :meth:`due` is true (-inf before the first reading):
        what a plugin's ``before_due``/``after_due`` returns for this gate."""
        if self.period <= 0.0 or self._next is None:
            return -INF
        return self._next

    def reset(self):
        self._next = None


def convert(text, cast, what):
    """``cast(text)`` for a configuration value, with bool understanding true/false/1/0 and
    floats required to be finite; PluginError naming ``what`` otherwise."""
    if cast is bool:
        low = text.strip().lower()
        if low in ("true", "1", "yes", "on"):
            return True
        if low in ("false", "0", "no", "off"):
            return False
        raise PluginError("%s: '%s' is not a boolean (true/false)" % (what, text))
    try:
        value = cast(text)
    except (TypeError, ValueError):
        raise PluginError("%s: '%s' is not a valid %s" % (what, text, getattr(cast, "__name__", cast)))
    if isinstance(value, float) and not math.isfinite(value):
        raise PluginError("%s: '%s' is not a finite number" % (what, text))
    return value


def sdf_pose(text, what):
    """An SDF ``<pose>`` "x y z roll pitch yaw" as ((x, y, z), (qx, qy, qz, qw)); "" = identity."""
    if not text:
        return ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
    parts = text.split()
    if len(parts) != 6:
        raise PluginError("%s: '%s' needs 6 numbers (x y z roll pitch yaw)" % (what, text))
    v = [convert(p, float, what) for p in parts]
    return (tuple(v[:3]), tuple(quat_from_rpy(*v[3:])))

"""What every controller shares: name, type, claimed joints, the state machine the controller
manager drives (initialized -> running <-> stopped), and a thread-safe command buffer."""
import math
import threading

from modrob_sim.ros_control.transmissions import CPP_NAMES


class CommandBuffer(object):
    """ros_controllers' realtime_tools::RealtimeBuffer: ROS callbacks write, the loop reads.
    ``version`` counts the writes (a controller compares it to know that a command waits);
    ``on_write`` (set by the plugin: its context's wake) is called after each write."""

    def __init__(self, value=0.0):
        self._lock = threading.Lock()
        self._value = value
        self.version = 0
        self.on_write = None

    def write(self, value):
        with self._lock:
            self._value = value
            self.version += 1
        cb = self.on_write
        if cb is not None:
            cb()

    def read(self):
        with self._lock:
            return self._value


class CommandResult(object):
    """What became of one command: ``accepted`` (False for NaN/inf), ``value`` stored,
    ``clamped_from`` the original value when it was limited to the joint range."""
    __slots__ = ("accepted", "value", "clamped_from", "reason")

    def __init__(self, accepted, value=None, clamped_from=None, reason=""):
        self.accepted, self.value, self.clamped_from, self.reason = accepted, value, clamped_from, reason


def check_finite(value, what):
    try:
        value = float(value)
    except (TypeError, ValueError):
        return None, CommandResult(False, reason="%s %r is not a number: ignored" % (what, value))
    if not math.isfinite(value):
        return None, CommandResult(False, reason="%s %r is not finite: ignored" % (what, value))
    return value, None


class Controller(object):
    TYPE = ""
    INTERFACE = None          # transmissions.EFFORT / POSITION / VELOCITY, or None (state only)
    STATE_INTERFACE = "hardware_interface::JointStateInterface"

    def __init__(self, name, hw, params):
        self.name = name
        self.hw = hw
        self.params = params
        self.state = "initialized"
        self.joint_names = []
        self.pending = None     # data the ROS layer publishes after this update (or None)

    @property
    def claimed_resources(self):
        """[(hardware interface C++ name, [joint names])] as controller_manager lists them."""
        if self.INTERFACE is None:
            return [(self.STATE_INTERFACE, [])]
        return [(CPP_NAMES[self.INTERFACE], list(self.joint_names))]

    def starting(self, t):
        pass

    def update(self, t, dt):
        pass

    def stopping(self, t):
        pass

    #: True after an update whose results come from the step's actuators: the plugin calls
    #: :meth:`collect` after that step (its ``pending`` is then filled)
    collect_due = False

    def update_due(self, t, iteration, dt):
        """The simulated time of the next update that must run in Python, asked at the step that
        starts at ``t`` (``iteration`` its index, ``dt`` the step): between two such updates the
        World's actuators carry the controller's last set-points (docs/plugins.md, "Due times").
        The default, ``t``: every update runs (a controller that writes new commands at every
        update). ``math.inf``: none until something changes. At a step where the World stops for
        another controller or plugin, an update that is not due is left out (ros_control's
        ControlLoop), unless ``update_at_every_stop``."""
        return t

    #: True: the update runs wherever the control loop updates, due or not (a controller whose
    #: results depend on how many updates there were: the mobile bases' odometry integrates the
    #: wheels' travel per update); False: only where :meth:`update_due` makes the World stop
    update_at_every_stop = False

    #: the ``command`` buffer's version the last update took (None: none taken yet)
    _taken_version = None

    def command_waiting(self):
        """True when the ``command`` buffer was written after the last :meth:`take_command`
        (a controller whose update only forwards its command is due then, and only then)."""
        return self.command.version != self._taken_version

    def take_command(self):
        """The ``command`` buffer's value, marked as taken (a write after the version is read
        makes the next update due again, so no command is missed)."""
        self._taken_version = self.command.version
        return self.command.read()

    def collect(self):
        """After the step of an update that set ``collect_due``: ``pending`` from what the
        actuators did in that step."""
        self.collect_due = False

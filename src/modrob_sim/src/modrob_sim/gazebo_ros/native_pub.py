"""roscpp publishers in the /gazebo node's process (``libmodrob_roscpp_pub.so``, loaded with ctypes).

A rospy publish costs ~100 us of CPU per message and subscriber (rospy hands each message to a
Python thread per connection, under the GIL): at 1000 /clock messages per second that is more
than the physics. :class:`NativePublisher` serialises the message once with rospy's own
``serialize_message`` (so the bytes, header seq included, are what rospy would send) and hands
them to a roscpp publisher, whose transport threads write them without the GIL.

The roscpp side is a second node in the same process, named ``<node>_roscpp`` (a node name can be
registered once; roscpp and rospy each register their own), in the node's namespace. It publishes
the topics; rospy keeps the services, parameters and subscriptions.

:func:`publisher` is the factory the node uses: a NativePublisher once :func:`start` succeeded,
else rospy.Publisher. Both offer ``publish``, ``get_num_connections``, ``resolved_name``, ``name``,
``unregister``. The node starts it unless its one switch, ``~native_publishing`` (default true),
is false (docs/simulator.md).
"""
import atexit
import ctypes
import io
import logging
import threading

LIBRARY = "libmodrob_roscpp_pub.so"
LOG = logging.getLogger("modrob_sim.gazebo_ros.native_pub")

_lib = None
_state = {"tried": False, "ok": False, "reason": "not started"}
_lock = threading.Lock()


def _load():
    from modrob_sim.physics.native import find_library
    path = find_library(LIBRARY)
    lib = ctypes.CDLL(path)
    # The calls the simulation thread makes in every pass keep the GIL (ctypes.PyDLL): each takes
    # microseconds, and releasing the GIL for it let a rospy thread of the node take it, so that
    # the simulation thread then waited for it. roscpp's threads never need the GIL.
    held = ctypes.PyDLL(path)
    for name in ("mrp_publish", "mrp_publish_deferred", "mrp_flush", "mrp_num_subscribers", "mrp_clock_tick",
                 "mrp_clock_last_t"):
        setattr(lib, name, getattr(held, name))
    # mrp_publish for a ctypes buffer, passed as it is (a cast to c_char_p per call cost ~3 us)
    lib.mrp_publish_buffer = held["mrp_publish"]
    lib.mrp_publish_buffer.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_uint32]
    lib.mrp_publish_buffer.restype = ctypes.c_int
    lib.mrp_init.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p]
    lib.mrp_init.restype = ctypes.c_int
    lib.mrp_error.restype = ctypes.c_char_p
    lib.mrp_advertise.argtypes = [ctypes.c_char_p] * 4 + [ctypes.c_int, ctypes.c_int]
    lib.mrp_advertise.restype = ctypes.c_void_p
    lib.mrp_publish.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_uint32]
    lib.mrp_publish.restype = ctypes.c_int
    lib.mrp_publish_deferred.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_uint32]
    lib.mrp_publish_deferred.restype = ctypes.c_int
    lib.mrp_flush.argtypes = [ctypes.c_void_p]
    lib.mrp_flush.restype = ctypes.c_int
    lib.mrp_num_subscribers.argtypes = [ctypes.c_void_p]
    lib.mrp_num_subscribers.restype = ctypes.c_int
    lib.mrp_unadvertise.argtypes = [ctypes.c_void_p]
    lib.mrp_clock_new.argtypes = [ctypes.c_void_p, ctypes.c_double]
    lib.mrp_clock_new.restype = ctypes.c_void_p
    lib.mrp_clock_free.argtypes = [ctypes.c_void_p]
    lib.mrp_clock_set_period.argtypes = [ctypes.c_void_p, ctypes.c_double]
    lib.mrp_clock_tick.argtypes = [ctypes.c_void_p, ctypes.c_double]
    lib.mrp_clock_tick.restype = ctypes.c_int
    lib.mrp_clock_last_t.argtypes = [ctypes.c_void_p]
    lib.mrp_clock_last_t.restype = ctypes.c_double
    lib.mrp_shutdown.restype = None
    return lib


def start(node_name):
    """Start the roscpp node beside the rospy node ``node_name`` (e.g. /gazebo). True when native
    publishing is available; else False and :func:`reason` says why."""
    global _lib
    with _lock:
        if _state["tried"]:
            return _state["ok"]
        _state["tried"] = True
        try:
            lib = _load()
        except OSError as exc:      # FileNotFoundError included: not built
            _state["reason"] = str(exc)
            return False
        import rosgraph
        ns, _, base = node_name.rstrip("/").rpartition("/")
        if lib.mrp_init((base + "_roscpp").encode(), (ns or "/").encode(),
                        rosgraph.get_master_uri().encode()) != 0:
            _state["reason"] = "roscpp did not start: %s" % lib.mrp_error().decode(errors="replace")
            return False
        _lib = lib
        _state["ok"] = True
        _state["reason"] = ""
        atexit.register(stop)
        return True


def reason():
    return _state["reason"]


def active():
    return _state["ok"]


def stop():
    """Shut the roscpp node down (its publishers unregister from the master)."""
    with _lock:
        if _state["ok"] and _lib is not None:
            _state["ok"] = False
            _lib.mrp_shutdown()


class NativePublisher(object):
    """rospy.Publisher's publishing side on roscpp: ``publish(msg)``, ``get_num_connections()``,
    ``resolved_name``/``name``, ``unregister()``. Thread-safe like rospy's."""

    def __init__(self, topic, msg_class, queue_size=1, latch=False):
        import rospy
        from rospy.msg import serialize_message
        self._serialize = serialize_message
        self.resolved_name = rospy.resolve_name(topic)
        self.name = self.resolved_name
        self.data_class = msg_class
        self.latch = bool(latch)
        self._seq = 0
        self._buf = io.BytesIO()
        self._lock = threading.Lock()
        h = _lib.mrp_advertise(self.resolved_name.encode(), msg_class._md5sum.encode(),
                               msg_class._type.encode(), msg_class._full_text.encode(), int(queue_size or 1),
                               int(self.latch))
        if not h:
            raise RuntimeError("roscpp could not advertise %s: %s" % (
                self.resolved_name, _lib.mrp_error().decode(errors="replace")))
        self._h = h

    def get_num_connections(self):
        h = self._h
        return _lib.mrp_num_subscribers(h) if h and _state["ok"] else 0

    def publish(self, msg):
        h = self._h
        if not h or not _state["ok"]:
            return
        # as rospy: nothing is serialised (and seq does not advance) without subscribers, except
        # on a latched topic, whose last message waits for the next subscriber
        if not self.latch and _lib.mrp_num_subscribers(h) == 0:
            return
        with self._lock:
            self._seq += 1
            b = self._buf
            b.seek(0)
            b.truncate(0)
            self._serialize(b, self._seq, msg)
            data = b.getvalue()
        _lib.mrp_publish(h, data[4:], len(data) - 4)

    def publish_serialized(self, buf, size):
        """Publish ``size`` bytes of ``buf`` (a ctypes buffer holding the serialised message
        without rospy's 4-byte length: the states of native_states)."""
        h = self._h
        if h and _state["ok"]:
            _lib.mrp_publish_buffer(h, buf, size)

    def clock_ticker(self, period):
        """A ClockTicker on this (/clock) publisher, or None when roscpp is not running."""
        h = self._h
        if not h or not _state["ok"]:
            return None
        return ClockTicker(_lib.mrp_clock_new(h, period))

    def flush(self):
        """Publish the deferred messages now (the /clock ticker's, after a pass of steps)."""
        h = self._h
        if h and _state["ok"]:
            _lib.mrp_flush(h)

    def unregister(self):
        h, self._h = self._h, None
        if h and _state["ok"]:
            _lib.mrp_unadvertise(h)


class ClockTicker(object):
    """/clock through roscpp at simulated times it is given (modrob_roscpp_pub.cpp): at every
    ``tick(t)`` or, with a ``period`` > 0, at most once per period of wall time; never twice for
    one time. ``observer`` is (function, argument) for World.set_step_observer: the World's native
    stretches then tick at every step they make, without Python. Deferred: the publisher's
    ``flush`` sends them."""

    def __init__(self, ptr):
        self._ptr = ptr
        self.observer = (ctypes.cast(_lib.mrp_clock_observe, ctypes.c_void_p).value, ptr)

    def tick(self, t):
        return bool(_lib.mrp_clock_tick(self._ptr, t))

    @property
    def last(self):
        """The simulated time of the last /clock sent (nan before the first)."""
        return _lib.mrp_clock_last_t(self._ptr)

    def set_period(self, period):
        _lib.mrp_clock_set_period(self._ptr, period)


def publisher(topic, msg_class, queue_size=1, latch=False):
    """A NativePublisher when native publishing is active (see :func:`start`), else rospy's."""
    if _state["ok"]:
        return NativePublisher(topic, msg_class, queue_size=queue_size, latch=latch)
    import rospy
    return rospy.Publisher(topic, msg_class, queue_size=queue_size, latch=latch)

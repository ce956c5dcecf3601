"""The camera renderer as part of the simulator: gzserver renders its own camera sensors, and so
does the /gazebo node, by running the renderer a package exports as a child process.

A package that can render the simulator's camera sensors says so in its ``package.xml``::

    <export><modrob_sim camera_renderer="camera_renderer"/></export>

(the value is an executable of that package, found as ``rosrun`` finds it; ``modrob_viz`` exports
its ``camera_renderer``). The simulator knows no renderer by name: it starts the first exported
one, with ``__name:=<node>_camera_renderer _sensors_param:=<node>/camera_sensors`` (where the camera
plugins register), on the renderer's private Xvfb (``~render_display`` names an X display instead).

When: like a Gazebo camera, which renders only while someone subscribes, the renderer is started
when one of the cameras' output topics has a subscriber, and stopped when none has had one for
``~render_idle_stop`` s, when the last camera is deleted, and when the node stops. A camera nobody
subscribes to costs the simulator nothing: no process, no tf listener. Inside the renderer a camera
without subscribers is not drawn either (docs/cameras.md).

The node advertises every output topic itself, as gzserver does (the camera plugins hand their
publishers to :meth:`RendererProcess.register`): ``rostopic echo`` / ``hz`` wait for a topic to be
advertised before they subscribe, and a subscriber connects to every publisher of a topic, so the
node's own (silent) publisher counts the subscribers; the renderer's publishes the images.
The counts are looked at every ``POLL`` s of wall time while a camera exists.

:class:`Demand` is the pure rule; :class:`RendererProcess` the thread and the child.
"""
import logging
import os
import shutil
import subprocess
import threading
import time

from modrob_sim import scenario_launch

LOG = logging.getLogger("modrob_sim.camera")

POLL = 0.5                  # s of wall time between two looks at the cameras' subscribers
STOP_TIMEOUT = 10.0         # s the renderer may take to end after SIGINT before it is killed


class Demand(object):
    """Whether the renderer should run (pure). ``update(now, cameras, subscribed)`` with the wall
    time, the number of registered cameras and whether one of their topics has a subscriber returns
    "start", "stop" or None (nothing to change)."""

    def __init__(self, idle_stop=10.0):
        self.idle_stop = float(idle_stop)
        self.running = False
        self.last_wanted = None

    def update(self, now, cameras, subscribed):
        if subscribed and cameras:
            self.last_wanted = now
            if not self.running:
                self.running = True
                return "start"
            return None
        if not self.running:
            return None
        idle = self.last_wanted is None or (self.idle_stop > 0 and now - self.last_wanted >= self.idle_stop)
        if cameras == 0 or idle:
            self.running = False
            return "stop"
        return None

    def exited(self):
        """The child ended by itself: start it again when it is wanted."""
        self.running = False


def check_display(value):
    """``~render_display``: "" (the renderer's private Xvfb) or an X display such as ":0" (to watch
    the renderer's panels); ValueError naming the parameter otherwise."""
    text = str(value).strip()
    if text == "" or (":" in text and " " not in text):
        return text
    raise ValueError("~render_display %r: give \"\" (the renderer's private Xvfb, the default) or an X "
                     "display such as ':0'" % (value,))


class RendererProcess(object):
    """One per simulator node. Camera plugins ``register(key, publishers)`` the publishers of their
    output topics (anything with ``get_num_connections()``) and ``unregister(key)`` them; a thread
    looks at their subscribers and runs the renderer as needed.

    ``exports`` is a package_exports.PackageExports; ``find_executable(package, name)`` -> path or
    None; ``popen`` starts the child (injectable for tests)."""

    _by_node = {}
    _lock = threading.Lock()

    @classmethod
    def for_node(cls, node_name, factory):
        """The node's RendererProcess (``factory()`` makes it on first use)."""
        with cls._lock:
            inst = cls._by_node.get(node_name)
            if inst is None or inst.closed:
                inst = cls._by_node[node_name] = factory()
            return inst

    def __init__(self, node_name, exports, find_executable, enabled=True, display="",
                 idle_stop=10.0, popen=None, poll=POLL):
        self.node_name = node_name.rstrip("/") or "/gazebo"
        self.exports = exports
        self.find_executable = find_executable
        self.enabled = enabled
        self.display = check_display(display)
        self.demand = Demand(idle_stop)
        self.popen = popen or _popen
        self.poll = poll
        self.cameras = {}           # key -> the publishers of its output topics
        self.child = None
        self.starts = 0
        self.closed = False
        self._command = None        # argv of the renderer, once found
        self._told = set()          # messages logged once
        self._lock = threading.Lock()
        self._wake = threading.Event()
        self._thread = None

    @property
    def sensors_param(self):
        return self.node_name + "/camera_sensors"

    @property
    def renderer_name(self):
        return self.node_name + "_camera_renderer"

    # ---- the plugins' side ---------------------------------------------------------------------
    def register(self, key, publishers):
        with self._lock:
            self.cameras[key] = list(publishers)
            if self._thread is None and not self.closed:
                self._thread = threading.Thread(target=self._run, name="camera_renderer_process",
                                                daemon=True)
                self._thread.start()
        self._wake.set()

    def unregister(self, key):
        with self._lock:
            self.cameras.pop(key, None)
        self._wake.set()

    # ---- the thread ----------------------------------------------------------------------------
    def _run(self):
        # the child's parent-death signal belongs to this thread: it lives as long as the child
        while not self.closed:
            with self._lock:
                publishers = [p for pubs in self.cameras.values() for p in pubs]
                count = len(self.cameras)
            self._reap()
            subscribed = self.enabled and any(p.get_num_connections() > 0 for p in publishers)
            action = self.demand.update(time.monotonic(), count, subscribed)
            if action == "start":
                self._start()
            elif action == "stop":
                self._stop("no camera is subscribed" if count else "no camera is left")
            self._wake.wait(self.poll)
            self._wake.clear()
        self._stop("the simulator stops")

    def _reap(self):
        if self.child is not None and self.child.poll() is not None:
            code = self.child.returncode
            self.child = None
            self.demand.exited()
            LOG.warning("camera renderer %s ended by itself (exit code %s); it is started again when a "
                        "camera is subscribed", self.renderer_name, code)

    def _find(self):
        """argv of the exported renderer, or None after saying (once) why there is none."""
        if self._command is not None:
            return self._command
        entries = self.exports.camera_renderers() if self.exports is not None else []
        for entry in entries:
            path = self.find_executable(entry.package, entry.executable)
            if path:
                self._command = [path]
                if len(entries) > 1:
                    self._once("several", logging.INFO, "camera renderer: %s of package '%s' (also "
                               "exported: %s)", entry.executable, entry.package,
                               ", ".join("%s/%s" % (e.package, e.executable) for e in entries[1:]))
                return self._command
            self._once("missing " + entry.package, logging.ERROR,
                       "camera renderer: package '%s' exports camera_renderer=\"%s\", but no such "
                       "executable was found in it; build the workspace (catkin_make)",
                       entry.package, entry.executable)
        self._once("none", logging.WARNING,
                   "camera sensors: no package on ROS_PACKAGE_PATH exports a camera renderer "
                   "(<export><modrob_sim camera_renderer=\"...\"/>, modrob_viz has one), so no images are "
                   "published; source the workspace that has modrob_viz")
        return None

    def _start(self):
        command = self._find()
        if command is None:
            return
        ns, _sep, name = self.renderer_name.rpartition("/")
        argv = command + ["__name:=" + name, "_sensors_param:=" + self.sensors_param]
        if self.display:
            argv.append("_display:=" + self.display)
        env = dict(os.environ)
        env["ROS_NAMESPACE"] = ns or "/"
        try:
            self.child = self.popen(argv, env)
        except OSError as exc:
            self.demand.exited()
            self._once("popen", logging.ERROR, "camera renderer %s could not be started: %s", argv[0], exc)
            return
        self.starts += 1
        LOG.info("camera renderer %s started (a camera is subscribed; pid %d)", self.renderer_name,
                 self.child.pid)

    def _stop(self, why):
        child, self.child = self.child, None
        if child is None or child.poll() is not None:
            return
        LOG.info("camera renderer %s stopped: %s", self.renderer_name, why)
        # the whole group: a renderer that restarted its crashed child must not leave it behind
        scenario_launch.stop(child, STOP_TIMEOUT)

    def _once(self, key, level, text, *args):
        if key not in self._told:
            self._told.add(key)
            LOG.log(level, text, *args)

    def shutdown(self):
        """Stop the renderer and the thread (the node stops)."""
        self.closed = True
        self._wake.set()
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join(STOP_TIMEOUT + 2.0)
        else:
            self._stop("the simulator stops")


def _popen(argv, env):
    """The renderer as a child that gets SIGTERM when this thread's process dies (``setpriv
    --pdeathsig``), in its own process group (a Ctrl-C in the terminal reaches the simulator, which
    stops it in order)."""
    prefix = ["setpriv", "--pdeathsig", "TERM"] if shutil.which("setpriv") else []
    return subprocess.Popen(prefix + argv, env=env, start_new_session=True)

"""What the /gazebo node publishes from the after-step hook: /clock (throttled to
~pub_clock_frequency of wall time), model and link states (~publish_rate of simulated time, built
only when subscribed), guard events, world markers (~marker_rate), the scene of every model's
visuals with per-link tf (~scene_rate) and performance metrics."""
import math
import time

import rospy
from gazebo_msgs import msg as gzm
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String
from visualization_msgs.msg import MarkerArray

from modrob_sim.camera.scene import ScenePublisher
from modrob_sim.gazebo_ros import markers, native_states
from modrob_sim.gazebo_ros.native_pub import publisher
from modrob_sim.gazebo_ros.conversions import pose_to_msg, ros_time, twist_to_msg
from modrob_sim.physics.world import FROZEN_REASON


def model_states_msg(world):
    """gazebo_msgs/ModelStates of ``world`` now."""
    ms = gzm.ModelStates()
    for name, model in world.models.items():
        ms.name.append(name)
        ms.pose.append(pose_to_msg(model.pose))
        ms.twist.append(twist_to_msg(model.twist))
    return ms


def link_states_msg(world):
    """gazebo_msgs/LinkStates of ``world`` now."""
    ls = gzm.LinkStates()
    for mname, model in world.models.items():
        for lname, link in model.links.items():
            ls.name.append("%s::%s" % (mname, lname))
            ls.pose.append(pose_to_msg(link.pose))
            ls.twist.append(twist_to_msg(link.twist))
    return ls


def set_clock(msg, t):
    """rosgraph_msgs/Clock ``msg`` := simulated time ``t`` (whole seconds, the rest rounded to
    nanoseconds; roscpp's ClockTicker makes the same bytes)."""
    c = msg.clock
    c.secs = int(t)
    c.nsecs = int(round((t - c.secs) * 1e9))
    if c.nsecs >= 1000000000:
        c.secs += 1
        c.nsecs -= 1000000000
    return msg


def _next_on_grid(t, period):
    """The first multiple of ``period`` after ``t`` (0 with no period: every step). The states and
    markers count their periods on this grid of simulated time (10, 20, .. ms at 100 Hz); the
    callers compare with half a step to spare, which absorbs the drift of the simulated time's
    float sum."""
    return (math.floor(t / period) + 1) * period if period > 0 else 0.0


class _NotAdvertised(object):
    """Stands in for a /gazebo topic when ~enable_ros_network is false: nothing is advertised."""

    def __init__(self, topic, *args, **kwargs):
        self.resolved_name = rospy.resolve_name(topic)

    def publish(self, msg):
        pass

    def get_num_connections(self):
        return 0


class StatePublishers(object):
    def __init__(self, world, params):
        self.world = world
        self.params = params
        # latched: a node that starts while the simulation is paused still learns the time
        self._clock_pub = publisher("/clock", Clock, queue_size=10, latch=True)
        self._clock_msg = Clock()
        # gazebo_ros's enable_ros_network false: /clock only, none of the /gazebo topics
        net = getattr(params, "enable_ros_network", True)
        native, plain = (publisher, rospy.Publisher) if net else (_NotAdvertised, _NotAdvertised)
        self._model_states_pub = native("~model_states", gzm.ModelStates, queue_size=1)
        self._link_states_pub = native("~link_states", gzm.LinkStates, queue_size=1)
        self._perf_pub = plain("~performance_metrics", gzm.PerformanceMetrics, queue_size=1)
        self._guard_pub = plain("~guard_events", String, queue_size=20)
        self._marker_pub = plain("~world_markers", MarkerArray, queue_size=1, latch=True)
        self._markers = markers.WorldMarkers(world, params.marker_models)
        # every model's visuals + per-link tf for RViz and the camera renderer (modrob_sim.camera)
        self._scene = ScenePublisher.for_world(world, params.scene_rate)
        self._guard_hint = {}
        # serialised states written by the C loop (native_states), per world layout
        self._native_states = native_states.available(world)
        self._states_cache = (None, None, None)     # (layout_version, model_states, link_states)

        self._clock_period = 1.0 / params.pub_clock_frequency if params.pub_clock_frequency > 0 else 0.0
        self._last_clock_wall = -1e9
        # with roscpp: /clock from the World's native steps too (its step observer), without Python
        ticker = getattr(self._clock_pub, "clock_ticker", None)
        self._ticker = ticker(self._clock_period) if ticker is not None else None
        if self._ticker is not None:
            world.set_step_observer(*self._ticker.observer)
        self._state_period = 1.0 / params.publish_rate if params.publish_rate > 0 else 0.0
        self._next_state_t = 0.0
        self._marker_period = 1.0 / params.marker_rate if params.marker_rate > 0 else 0.0
        self._markers_behind = False    # marker times passed with nobody subscribed
        self._next_marker_t = 0.0
        self._last_rtf_log = time.monotonic()
        self._rtf_log_from = (world.stops, world.time)     # the World's stops and time at the last log

    def flush_clock(self):
        """The /clock messages of the native steps so far leave now: before anything a hook
        publishes, so that a subscriber never gets a message stamped after the /clock it has."""
        if self._ticker is not None:
            self._clock_pub.flush()

    def after_step(self):
        now_t = self.world.time
        if self._ticker is not None:
            self._ticker.tick(now_t)    # at its period, once per time (the observer may have sent it)
            self._clock_pub.flush()
        elif self._clock_period <= 0.0:
            self.publish_clock()
        else:
            wall = time.monotonic()
            if wall - self._last_clock_wall >= self._clock_period:
                self._last_clock_wall = wall
                self.publish_clock()
        self._on_grid(now_t)
        self._scene.after_step(now_t)

    def _on_grid(self, now_t):
        """The states and markers whose grid time has come by ``now_t`` go out (with the guard's
        events); called wherever the World stops for Python (see after_due)."""
        half = 0.5 * self.world.time_step
        if now_t + half >= self._next_state_t:
            self._next_state_t = _next_on_grid(now_t + half, self._state_period)
            self.publish_states()
            self.report_guard_events()
        if self._marker_period > 0.0 and now_t + half >= self._next_marker_t:
            self._next_marker_t = _next_on_grid(now_t + half, self._marker_period)
            self.publish_markers()

    # ---- due times and the loop's passes (the World steps natively in between) --------------------
    def after_due(self):
        """The simulated time by which after_step must run (the World's due time for it): the
        states and markers within their periods; None (every step) when /clock goes out at every
        step and only rospy can send it."""
        if self._ticker is None and self._clock_period <= 0.0:
            return None
        # the states go out at the first step at or after their grid time at which the World stops
        # anyway (a sensor's sample, a controller's update, the end of the loop's pass), and make
        # the World stop only at the period's last step when nothing else did: a sensor or a
        # controller at the states' rate on another phase (an IMU counts its period from its first
        # step) would otherwise double the stops
        # the markers likewise
        dt = self.world.time_step
        due = self._next_state_t
        if self._state_period > 0.0:
            due += max(0.0, self._state_period - dt)
        if self._marker_period > 0.0:
            due = min(due, self._next_marker_t + max(0.0, self._marker_period - dt))
        return due - 0.5 * dt

    def after_pass(self):
        """After a pass of the simulation loop (world.step): the /clock messages of its native
        steps leave together (roscpp), or a throttled /clock through rospy; the states and markers
        whose grid time came; the scene's wall-clock schedule."""
        if self._ticker is not None:
            self._clock_pub.flush()
        elif self._clock_period > 0.0:
            wall = time.monotonic()
            if wall - self._last_clock_wall >= self._clock_period:
                self._last_clock_wall = wall
                self.publish_clock()
        self._on_grid(self.world.time)
        self._scene.after_step(self.world.time)

    def after_reset(self):
        """The simulated time jumped: publish everything now and restart the decimation."""
        self._next_state_t = 0.0
        self._next_marker_t = 0.0
        self.publish_clock()
        self.publish_states()
        self.publish_markers(force=True)

    def publish_clock(self):
        set_clock(self._clock_msg, self.world.time)
        self._clock_pub.publish(self._clock_msg)

    def publish_states(self):
        world = self.world
        if self._native_states and hasattr(self._model_states_pub, "publish_serialized"):
            self._publish_native_states()
            return
        if self._model_states_pub.get_num_connections() > 0:
            self._model_states_pub.publish(model_states_msg(world))
        if self._link_states_pub.get_num_connections() > 0:
            self._link_states_pub.publish(link_states_msg(world))

    def _publish_native_states(self):
        world = self.world
        ms_sub = self._model_states_pub.get_num_connections() > 0
        ls_sub = self._link_states_pub.get_num_connections() > 0
        if not (ms_sub or ls_sub):
            return
        version, ms, ls = self._states_cache
        if version != world.layout_version:
            ms = ls = None
            version = world.layout_version
        if ms_sub:
            if ms is None:
                ms = native_states.model_states(world)
            ms.publish(self._model_states_pub)
        if ls_sub:
            if ls is None:
                ls = native_states.link_states(world)
            ls.publish(self._link_states_pub)
        self._states_cache = (version, ms, ls)

    def publish_markers(self, force=False):
        # with nobody subscribed nothing is built: while a model moved, the array was made anew at
        # every marker time (36 markers of Bulbs and Slides: ~0.6 ms with rospy's serialisation
        # for the latch). A subscriber gets the latched array, then a fresh one at the next marker
        # time (the poses are compared with those last sent).
        if not force and self._marker_pub.get_num_connections() == 0:
            self._markers_behind = True
            return
        self._markers_behind = False
        arr = self._markers.update(force=force)
        if arr is not None:
            self._marker_pub.publish(arr)

    def on_pause(self):
        """The simulation pauses, or a step made while paused ends: /clock tells the exact paused
        time (the throttled clock may have skipped the last step), and markers left unbuilt while
        nobody subscribed are made now, so that a subscriber that comes while it is paused gets the
        world as it stands (both latched)."""
        self.publish_clock()
        if self._markers_behind:
            self.publish_markers(force=True)

    def report_guard_events(self):
        """Publish every guard event; the core logs each one, the node adds a hint at most every
        5 s per model (a model that keeps blowing up would flood the log otherwise)."""
        for ev in self.world.pop_events():
            self._guard_pub.publish(String(data="model=%s link=%s time=%.6f reason=%s"
                                           % (ev.model, ev.link, ev.time, ev.reason)))
            if ev.reason == FROZEN_REASON:
                continue  # the core's error names the model and what releases it
            wall = time.monotonic()
            if wall - self._guard_hint.get(ev.model, -1e9) >= 5.0:
                self._guard_hint[ev.model] = wall
                rospy.logerr("model '%s' (link '%s') blew up and was restored: check its controller gains, "
                             "commanded efforts, link masses/inertias and the time step; events on %s"
                             % (ev.model, ev.link, self._guard_pub.resolved_name))

    def forget_model(self, name):
        """A model was deleted: nothing of it stays in the publishers' caches (the scene's tf
        list is rebuilt at once, the markers' visuals and the guard hint dropped)."""
        self._guard_hint.pop(name, None)
        self._markers.forget_removed()
        self._scene.forget_removed()

    def publish_rtf(self, rtf, sim_time, paused):
        msg = gzm.PerformanceMetrics()
        msg.header.stamp = ros_time(sim_time)
        msg.real_time_factor = rtf
        self._perf_pub.publish(msg)
        wall = time.monotonic()
        if self.params.rtf_log_period > 0 and wall - self._last_rtf_log >= self.params.rtf_log_period:
            self._last_rtf_log = wall
            # at how many steps per simulated second hooks ran in Python since the last line: a
            # plugin due at every step shows here as ~1000 (at 1 ms), docs/simulator.md
            stops0, t0 = self._rtf_log_from
            stops = self.world.stops
            self._rtf_log_from = (stops, sim_time)
            per = "" if paused or sim_time <= t0 else ", hooks in Python at %d steps per simulated s" % round(
                (stops - stops0) / (sim_time - t0))
            rospy.loginfo("sim time %.2f s, real-time factor %.2f%s%s" % (
                sim_time, rtf, per, " (paused)" if paused else ""))

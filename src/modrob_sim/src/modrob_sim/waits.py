"""Waits for clients of the simulator (scenarios, teleops, tests), with limits in wall-clock time.

With ``use_sim_time`` set, actionlib's ``wait_for_server(timeout)``, ``rospy.sleep`` and
``rospy.get_time`` run on the simulator's clock: at ``real_time_factor`` 0 a minute of simulated
time can pass in a fraction of a wall second (before the controller spawner has even started the
action servers), and while the simulator is paused or not yet publishing ``/clock`` it never
passes. How long a client is willing to wait for the rest of the system is a wall-clock question.

The rule of this module: every ``timeout`` is wall seconds (``time.monotonic``) and ends the wait
whatever the simulated clock does. Simulated time is only ever what is waited *for*: the
``seconds`` of :func:`sim_sleep`, a message's stamp in ``Latest.after``. So a stopped clock (the
simulator paused, dead, or not publishing ``/clock`` yet) never hangs a wait: it runs out its
wall-clock limit and says so. A wait given ``what`` (a test's wait) raises AssertionError naming
it; one without returns False, for callers that decide themselves what a missed wait means. Waits
look at their condition every ``POLL`` wall seconds and give up at ROS shutdown.
"""
import threading
import time

import rospy

POLL = 0.01  # wall seconds between two looks at a condition


def wait_for_action_servers(clients, timeout):
    """Wait until every ``(SimpleActionClient, name)`` in ``clients`` has its server.

    Returns the name of the first server still missing after ``timeout`` wall seconds (or at
    shutdown), None when all are there.
    """
    end = time.monotonic() + timeout
    for client, name in clients:
        # the short sim-time timeout only bounds one look; the loop's limit is wall time
        while not client.wait_for_server(rospy.Duration(0.05)):
            if rospy.is_shutdown() or time.monotonic() > end:
                return name
            time.sleep(POLL)
    return None


def wait_until(condition, timeout, what=None, period=POLL):
    """Look at ``condition()`` every ``period`` wall seconds until it is true, for at most
    ``timeout`` wall seconds. Its true value once it is (a message, a state to judge);
    otherwise (the limit passed, or ROS shut down) False, or with ``what`` AssertionError "timed
    out after <timeout> s waiting for <what>"."""
    end = time.monotonic() + timeout
    while not rospy.is_shutdown():
        value = condition()
        if value:
            return value
        if time.monotonic() > end:
            break
        time.sleep(period)
    if what is None:
        return False
    raise _missed(timeout, what)


def _missed(timeout, what):
    if rospy.is_shutdown():
        return AssertionError("ROS shut down while waiting for %s" % what)
    return AssertionError("timed out after %.0f s waiting for %s" % (timeout, what))


def sim_sleep(seconds, timeout=60.0):
    """Wait until this node's simulated clock (``rospy.get_time()``) has advanced ``seconds`` from
    its value now, for at most ``timeout`` wall seconds; AssertionError after that, saying whether
    the clock stood still (the simulator paused, or no ``/clock``) or only ran slower than that.
    Unlike ``rospy.sleep`` it never waits forever on a stopped clock and does not raise when the
    clock jumps back (a world reset: it then waits until the clock is at the end again). Before the
    node's first ``/clock`` message its time is 0, so wait for something the simulator publishes
    first. A test's wait: the caller resumes within ``POLL`` wall seconds of the end, which at a
    high real-time factor is some simulated time past it."""
    start = rospy.get_time()
    end = start + seconds
    if wait_until(lambda: rospy.get_time() >= end, timeout):
        return
    now = rospy.get_time()
    if rospy.is_shutdown():
        raise AssertionError("ROS shut down during a sleep of %g s of simulated time" % seconds)
    if now == start:
        raise AssertionError("the simulated clock stood still at %.3f s for %.0f wall s (a sleep of %g s of "
                             "simulated time): is the simulator paused, or not publishing /clock?"
                             % (now, timeout, seconds))
    raise AssertionError("timed out after %.0f s: the simulated clock went from %.3f s to %.3f s of the "
                         "%.3f s a sleep of %g s needs" % (timeout, start, now, end, seconds))


def controller_states(ns, timeout=60.0):
    """``{controller name: state}`` from ``<ns>/controller_manager/list_controllers``, waiting up to
    ``timeout`` wall seconds for that service (rospy.ROSException naming it after that)."""
    from controller_manager_msgs.srv import ListControllers
    name = ns.rstrip("/") + "/controller_manager/list_controllers"
    rospy.wait_for_service(name, timeout=timeout)
    return {c.name: c.state for c in rospy.ServiceProxy(name, ListControllers)().controller}


def wait_running(ns, names, timeout=60.0):
    """Wait until each of the controllers ``names`` of the controller manager in ``ns`` is running
    (its spawner has loaded and started it), for at most ``timeout`` wall seconds in all;
    AssertionError naming them and their states after that. One list_controllers call per look,
    a look every 0.2 s (a service call is a round trip through the simulator's node)."""
    end = time.monotonic() + timeout
    states = {}

    def running():
        states.update(controller_states(ns, max(end - time.monotonic(), 0.1)))
        return all(states.get(n) == "running" for n in names)
    if not wait_until(running, timeout, period=0.2):
        raise _missed(timeout, "controllers %s running in %s (their states: %s)"
                      % (", ".join(names), ns, states))


def command_publisher(topic, cls, timeout):
    """A latched publisher of ``cls`` on ``topic``, returned once a subscriber (the simulator, a
    controller) is connected to it. A command published before that would wait for the connection
    while the simulation runs on (at a high real-time factor a connection takes seconds of
    simulated time); latched, the last command also reaches a subscriber that reconnects.
    Raises rospy.ROSException (as rospy's own waits do) when nobody has connected after
    ``timeout`` wall seconds."""
    pub = rospy.Publisher(topic, cls, queue_size=1, latch=True)
    if not wait_until(lambda: pub.get_num_connections() > 0, timeout):
        raise rospy.ROSException("nobody subscribed to %s within %.0f s: is the node that takes these "
                                 "commands running (`rostopic info %s`)?" % (pub.resolved_name, timeout,
                                                                             pub.resolved_name))
    return pub


def lookup_transform(buffer, target, source, timeout):
    """``buffer.lookup_transform(target, source, latest)``, waiting up to ``timeout`` wall seconds
    for it to become known (tf2's own timeout is simulated time: at a high real-time factor its
    second is gone before a just-created TransformListener has its connections). Raises tf2's
    exception of the last look when it is still unknown."""
    import tf2_ros
    end = time.monotonic() + timeout
    while True:
        try:
            return buffer.lookup_transform(target, source, rospy.Time(0))
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException):
            if rospy.is_shutdown() or time.monotonic() > end:
                raise
        time.sleep(POLL)


def wait_for_result(client, timeout):
    """``client.wait_for_result`` (a SimpleActionClient) with a limit of ``timeout`` wall seconds:
    True once its goal is done. actionlib's limit is simulated time and is checked before the
    goal's state: a client that was not scheduled for a wall second at real_time_factor 0 wakes up
    past a 60 s limit and says "no result" although the result came with the clock."""
    from actionlib import SimpleGoalState
    if client.gh is None:
        raise ValueError("no goal sent on %s: send_goal first" % client.action_client.ns)
    return wait_until(lambda: client.simple_state == SimpleGoalState.DONE, timeout)


def result_time(client):
    """The simulated time at which the server decided the result ``client`` (a SimpleActionClient)
    has just received: its result message's stamp. A check of the state "after the goal ended"
    reads messages stamped from then on (``Latest.after``); this node's own clock can be a
    simulated second behind the result it has taken."""
    result = client.gh.comm_state_machine.latest_result if client.gh else None
    if result is None:
        raise ValueError("no result received on %s yet: wait_for_result first" % client.action_client.ns)
    return result.header.stamp.to_sec()


def stop_following_clock():
    """For a node that needs no simulated time any more (it only serves or waits for shutdown,
    with wall-clock timeouts): drop rospy's /clock subscription. With ``use_sim_time`` every rospy
    node subscribes to /clock at init_node, and an idle one still takes every message (~150 us of
    CPU each at the launch files' 250 per wall second: 4 % of a core per node, beside a simulator
    that wants the cores). rospy's time then stays at the last /clock received (the stamps of
    its later log messages too). True when a subscription was dropped."""
    from rospy.impl import simtime
    sub = getattr(simtime, "_clock_sub", None)
    if sub is None:
        return False
    sub.unregister()
    simtime._clock_sub = None
    return True


class Latest(object):
    """The latest message of a topic (and, with ``keep``, every one), for checks that read what a
    simulator publishes.

    At ``real_time_factor`` 0 the simulator publishes thousands of messages per wall second: the
    one a subscriber has just taken can be simulated seconds older than the simulator's clock (it
    waited in the sockets), and some never arrive (a publisher's queue overflows). So a check that
    knows the simulated time of an event reads ``after(t)``, the first message stamped at ``t`` or
    later, and one that reads a history checks it has no gap where it matters. Waits are in wall
    seconds (this module's rule).

    ``queue_size`` (default: every message) and ``buff_size`` are rospy.Subscriber's: images want
    ``queue_size=1`` (only the newest counts) and a ``buff_size`` that holds one."""

    def __init__(self, topic, cls, keep=False, queue_size=None, buff_size=65536):
        self.cls = cls
        self.topic = topic
        self.stamped = bool(cls._slot_types) and cls._slot_types[0] == "std_msgs/Header"
        self.lock = threading.Lock()
        self.count = 0
        self.msg = None
        self._kept = [] if keep else None
        self._times = []
        self.sub = rospy.Subscriber(topic, cls, self._take, queue_size=queue_size, buff_size=buff_size)

    def _take(self, msg):
        with self.lock:
            self.msg = msg
            self.count += 1
            if self._kept is not None:
                self._kept.append(msg)
                self._times.append(rospy.get_time())

    def get(self):
        return self.msg

    @property
    def history(self):
        """Every message since the start or ``clear()`` (``keep=True``), oldest first."""
        if self._kept is None:
            raise ValueError("Latest(%s) keeps no history: create it with keep=True" % self.topic)
        with self.lock:
            return list(self._kept)

    @property
    def received(self):
        """``(this node's simulated time at its receipt, message)`` of every message kept: the only
        time a header-less message (a std_msgs/Float64 command) has. A receipt is late by the
        delivery, so judge rates by many of them, never one interval."""
        if self._kept is None:
            raise ValueError("Latest(%s) keeps no history: create it with keep=True" % self.topic)
        with self.lock:
            return list(zip(self._times, self._kept))

    def clear(self):
        with self.lock:
            if self._kept is not None:
                self._kept = []
                self._times = []

    def wait_connected(self, timeout=30.0):
        """Wait up to ``timeout`` wall seconds for a connection to a publisher of the topic: what
        is published before it is not received (at real_time_factor 0 a whole action can run in
        less time than a connection takes). Returns self."""
        if not wait_until(lambda: self.sub.get_num_connections() > 0, timeout):
            raise AssertionError("no publisher of %s connected within %.0f s" % (self.topic, timeout))
        return self

    def wait(self, cond=lambda m: True, timeout=30.0, what=None):
        """Wait up to ``timeout`` wall seconds for a latest message that satisfies ``cond``; return
        it. AssertionError (naming ``what``) when none came."""
        found = []

        def ready():
            m = self.msg
            if m is not None and cond(m):
                found.append(m)
            return bool(found)
        wait_until(ready, timeout, "%s on %s" % (what or "a message", self.topic))
        return found[0]

    def after(self, t, timeout=30.0):
        """The first message stamped at simulated time ``t`` or later (with ``keep``; else the
        latest once it is that young), waiting up to ``timeout`` wall seconds for it."""
        if not self.stamped:
            raise TypeError("%s has no header stamp (%s)" % (self.topic, self.cls._type))

        def young(m):
            return m.header.stamp.to_sec() >= t
        latest = self.wait(young, timeout, "a message of simulated time %.3f or later" % t)
        if self._kept is None:
            return latest
        return next(m for m in self.history if young(m))

    def fresh(self, timeout=30.0):
        """The first message stamped at the simulated time this node knows now, or later."""
        return self.after(rospy.get_time(), timeout)


class GraphWait(object):
    """Wait from a shell for a ROS graph to be up: the master, then each name as an advertised
    service or as a topic that has delivered one message (``rosrun modrob_sim wait_for``).

    ROS 1's ``rostopic``/``rosservice``/``rosparam`` give up at once ("Unable to communicate with
    master!") when they run before the master of a ``roslaunch ... &`` is up, and ``rosservice``
    has no ``wait``; this is the missing piece between a backgrounded launch and the next command.
    ``master`` is a ``rosgraph.Master``; ``subscribe(topic, callback)`` makes a subscription (in a
    node, after the master is up) and returns it; ``bus_info(node)`` is that node's getBusInfo
    connections (ROS's slave API: ``[id, peer, direction, transport, topic, connected, ...]``),
    for the topics waited on until a subscriber of theirs is connected (``--subscribed``).
    """

    def __init__(self, master, subscribe, bus_info=None):
        self.master = master
        self.subscribe = subscribe
        self.bus_info = bus_info or self._bus_info
        self.subscriptions = {}
        self.received = set()

    def master_up(self):
        try:
            self.master.getPid()
            return True
        except Exception:  # noqa: B902 - any failure to reach the master means "not yet"
            return False

    def _state(self):
        try:
            publishers, _subscribers, services = self.master.getSystemState()
        except Exception:  # noqa: B902 - the master went away (launch ended): not there
            return set(), set()
        return {t for t, _ in publishers}, {s for s, _ in services}

    def pending(self, names):
        """The names not there yet (subscribing to those that became published topics)."""
        topics, services = self._state()
        left = []
        for name in names:
            if name in services or name in self.received:
                continue
            if name in topics and name not in self.subscriptions:
                self.subscriptions[name] = self.subscribe(
                    name, lambda _msg, n=name: self.received.add(n))
            left.append(name)
        return left

    def unsubscribed(self, topics):
        """The ``topics`` no node subscribes to with a live connection yet:
        registered at the master and connected to a publisher, so that what is published next
        reaches it (a plot started in the background before a step is commanded)."""
        return [topic for topic in topics if not self.connected_subscribers(topic)]

    def connected_subscribers(self, topic):
        """The nodes subscribed to ``topic`` with a live connection to a publisher of it (whichever
        node publishes it: /gazebo's topics may come from its roscpp side, /gazebo_roscpp)."""
        try:
            _publishers, subscribers, _services = self.master.getSystemState()
        except Exception:  # noqa: B902 - the master went away (launch ended): not there
            return []
        return [node for node in dict(subscribers).get(topic, ()) if self._connected(node, topic)]

    def _connected(self, node, topic):
        try:
            connections = self.bus_info(node)
        except Exception:  # noqa: B902 - a node that went away or does not answer yet: not connected
            return False
        return any(c[4] == topic and c[2] == "i" and (len(c) < 6 or c[5]) for c in connections)

    def _bus_info(self, node):
        import xmlrpc.client
        code, _msg, connections = xmlrpc.client.ServerProxy(self.master.lookupNode(node)).getBusInfo(
            self.master.caller_id)
        return connections if code == 1 else []

    def kind(self, name):
        return "topic" if name in self.subscriptions else "service or topic"

    def close(self):
        for sub in self.subscriptions.values():
            sub.unregister()
        self.subscriptions.clear()


def wait_for_graph(names, timeout, log=print, subscribed=()):
    """The command line's body: wait up to ``timeout`` wall seconds for the master, ``names`` and
    a connected subscriber on each topic of ``subscribed``.
    Returns 0 when all are there, 1 (after saying which are missing and why) otherwise."""
    import rosgraph
    start = time.monotonic()
    graph = GraphWait(rosgraph.Master("/wait_for"),
                      lambda topic, callback: rospy.Subscriber(topic, rospy.AnyMsg, callback))
    uri = rosgraph.get_master_uri()
    if not _poll(graph.master_up, start + timeout):
        log("wait_for: no ROS master at %s within %.0f s: start a launch file (roslaunch ... &) or roscore "
            "first, or check ROS_MASTER_URI" % (uri, timeout))
        return 1
    left = list(names)
    if left:
        rospy.init_node("wait_for", anonymous=True, disable_rosout=True, disable_rostime=True)
        ok = _poll(lambda: not graph.pending(left), start + timeout)
        left = graph.pending(left)
        graph.close()
        if not ok and left:
            log("wait_for: not there after %.0f s: %s (no such service, and no message on such a topic; "
                "`rosservice list` and `rostopic list` show what there is)"
                % (timeout, ", ".join("%s (%s)" % (n, graph.kind(n)) for n in left)))
            return 1
    if subscribed:  # after graph.close(): this node's own subscriptions are gone
        _poll(lambda: not graph.unsubscribed(subscribed), start + timeout)
        left = graph.unsubscribed(subscribed)
        if left:
            log("wait_for: nobody subscribes to %s with a connection after %.0f s (`rostopic info TOPIC` "
                "shows its publishers and subscribers)" % (", ".join(left), timeout))
            return 1
    there = [uri] + list(names) + ["subscriber of %s" % t for t in subscribed]
    log("wait_for: %s up after %.1f s" % (", ".join(there), time.monotonic() - start))
    return 0


def _poll(condition, end):
    """``condition()`` every POLL wall seconds until it is true (True) or ``end`` passes (False)."""
    while True:
        if condition():
            return True
        if time.monotonic() > end:
            return False
        time.sleep(POLL)

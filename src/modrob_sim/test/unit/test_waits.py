"""modrob_sim.waits: limits in wall time, whatever the simulated clock does."""
import time

from modrob_sim import waits


class FakeClient(object):
    """A SimpleActionClient whose server appears after ``ready_after`` looks (None: never)."""

    def __init__(self, ready_after):
        self.ready_after = ready_after
        self.looks = 0

    def wait_for_server(self, timeout):
        self.looks += 1
        return self.ready_after is not None and self.looks > self.ready_after


def test_servers_that_come_up_late_are_waited_for():
    arm, gripper = FakeClient(3), FakeClient(0)
    assert waits.wait_for_action_servers(((arm, "arm"), (gripper, "gripper")), 10.0) is None
    assert arm.looks == 4 and gripper.looks == 1


def test_a_missing_server_is_named_after_the_wall_clock_limit():
    arm, gripper = FakeClient(0), FakeClient(None)
    start = time.monotonic()
    assert waits.wait_for_action_servers(((arm, "arm"), (gripper, "gripper")), 0.2) == "gripper"
    assert time.monotonic() - start >= 0.2
    assert gripper.looks > 1


def bounded(fn, limit):
    """``fn()`` in a thread: its result or exception, failing the test (instead of hanging it) when
    it has not returned after ``limit`` wall seconds (a wait that never times out)."""
    import threading
    out = {}

    def run():
        try:
            out["value"] = fn()
        except BaseException as e:  # noqa: B902 - handed to the test
            out["error"] = e
    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    thread.join(limit)
    assert not thread.is_alive(), "still waiting after %s wall s" % limit
    if "error" in out:
        raise out["error"]
    return out["value"]


def test_wait_until():
    calls = []
    assert waits.wait_until(lambda: calls.append(1) or len(calls) > 2, 10.0)
    assert len(calls) == 3
    states = iter([None, [], {"box": 1}])
    assert waits.wait_until(lambda: next(states), 10.0) == {"box": 1}      # the value, to be judged
    start = time.monotonic()
    assert bounded(lambda: waits.wait_until(lambda: False, 0.1), 5) is False
    assert time.monotonic() - start >= 0.1


def test_wait_until_with_what_fails_the_test_naming_it_after_the_wall_clock_limit():
    import pytest
    assert waits.wait_until(lambda: True, 0.1, "nothing") is True
    looks = []
    start = time.monotonic()
    with pytest.raises(AssertionError, match=r"^timed out after 0 s waiting for the arm at rest$"):
        bounded(lambda: waits.wait_until(lambda: looks.append(1), 0.3, "the arm at rest", period=0.05), 5)
    assert time.monotonic() - start >= 0.3
    assert 4 <= len(looks) <= 8        # one look every period, not a busy loop


class FakeClock(object):
    """rospy.get_time of a simulator: ``step`` simulated seconds more at each look."""

    def __init__(self, t, step):
        self.t, self.step, self.looks = t, step, 0

    def __call__(self):
        self.looks += 1
        self.t += self.step
        return self.t


def test_sim_sleep_waits_for_simulated_time(monkeypatch):
    import rospy
    clock = FakeClock(10.0, 0.1)
    monkeypatch.setattr(rospy, "get_time", clock)
    bounded(lambda: waits.sim_sleep(2.0, timeout=10.0), 5)
    assert clock.t >= 12.0 and clock.looks >= 20     # not back before the 2 s had passed
    # a world reset sets the clock back: the sleep waits until the end comes again
    times = iter([5.0, 5.5, 0.2, 1.0, 4.9, 6.0])
    monkeypatch.setattr(rospy, "get_time", lambda: next(times))
    bounded(lambda: waits.sim_sleep(1.0, timeout=10.0), 5)
    assert next(times, None) is None


def test_sim_sleep_on_a_stopped_clock_fails_after_its_wall_clock_limit(monkeypatch):
    import pytest
    import rospy
    monkeypatch.setattr(rospy, "get_time", FakeClock(3.25, 0.0))
    start = time.monotonic()
    with pytest.raises(AssertionError, match=r"simulated clock stood still at 3.250 s for 0 wall s.*"
                                             r"paused, or not publishing /clock"):
        bounded(lambda: waits.sim_sleep(1.0, timeout=0.3), 5)
    assert time.monotonic() - start >= 0.3
    monkeypatch.setattr(rospy, "get_time", FakeClock(3.0, 1e-6))     # moving, far too slowly
    with pytest.raises(AssertionError, match=r"timed out after 0 s: the simulated clock went from 3.000 s "
                                             r"to 3.0\d\d s of the 4.000 s a sleep of 1 s needs"):
        bounded(lambda: waits.sim_sleep(1.0, timeout=0.3), 5)


class FakeControllerManager(object):
    """rospy.wait_for_service + ServiceProxy of a controller manager whose controllers are listed
    as ``states`` after ``ready_after`` list_controllers calls (loaded, not started, before)."""

    def __init__(self, states, ready_after):
        self.states, self.ready_after, self.calls, self.waited = states, ready_after, 0, []

    def wait_for_service(self, name, timeout=None):
        self.waited.append((name, timeout))

    def ServiceProxy(self, name, cls):
        import types

        def call():
            self.calls += 1
            now = self.states if self.calls > self.ready_after else {n: "initialized" for n in self.states}
            return types.SimpleNamespace(controller=[types.SimpleNamespace(name=n, state=s)
                                                     for n, s in now.items()])
        return call


def test_wait_running_until_every_controller_is_running(monkeypatch):
    import pytest
    import rospy
    manager = FakeControllerManager({"joint_state_controller": "running", "arm_controller": "running"}, 2)
    monkeypatch.setattr(rospy, "wait_for_service", manager.wait_for_service)
    monkeypatch.setattr(rospy, "ServiceProxy", manager.ServiceProxy)
    bounded(lambda: waits.wait_running("/arm1", ["joint_state_controller", "arm_controller"], 10.0), 5)
    assert manager.calls == 3
    assert manager.waited[0][0] == "/arm1/controller_manager/list_controllers"
    assert 0 < manager.waited[-1][1] <= 10.0       # the service's wait takes what is left of the limit
    assert waits.controller_states("/") == {"joint_state_controller": "running", "arm_controller": "running"}
    assert manager.waited[-1][0] == "/controller_manager/list_controllers"
    manager = FakeControllerManager({"joint_state_controller": "running", "arm_controller": "stopped"}, 0)
    monkeypatch.setattr(rospy, "wait_for_service", manager.wait_for_service)
    monkeypatch.setattr(rospy, "ServiceProxy", manager.ServiceProxy)
    start = time.monotonic()
    said = (r"timed out after 1 s waiting for controllers joint_state_controller, arm_controller "
            r"running in /arm1 \(their states: .*'arm_controller': 'stopped'")
    with pytest.raises(AssertionError, match=said):
        bounded(lambda: waits.wait_running("/arm1", ["joint_state_controller", "arm_controller"], 0.6), 5)
    assert time.monotonic() - start >= 0.6
    assert 3 <= manager.calls <= 5                 # a look every 0.2 s: a service call each


class FakeTfBuffer(object):
    """A tf2_ros.Buffer that knows the transform from the ``known_after``-th look on (None: never)."""

    def __init__(self, known_after):
        self.known_after = known_after
        self.looks = 0

    def lookup_transform(self, target, source, stamp, timeout=None):
        import tf2_ros
        self.looks += 1
        assert timeout is None        # the wait is in wall time, never tf2's simulated-time timeout
        if self.known_after is None or self.looks <= self.known_after:
            raise tf2_ros.LookupException('"%s" passed to lookupTransform argument target_frame does '
                                          'not exist' % target)
        return (target, source)


def test_lookup_transform_waits_in_wall_time_then_raises_tf2s_exception():
    import pytest
    import tf2_ros
    late = FakeTfBuffer(known_after=3)
    assert waits.lookup_transform(late, "base", "world", 10.0) == ("base", "world")
    assert late.looks == 4
    never = FakeTfBuffer(known_after=None)
    start = time.monotonic()
    with pytest.raises(tf2_ros.LookupException, match="base"):
        waits.lookup_transform(never, "base", "world", 0.2)
    assert time.monotonic() - start >= 0.2 and never.looks > 1


class FakePublisher(object):
    """rospy.Publisher with a subscriber connecting at the ``connect_after``-th look (None: never)."""
    connect_after = None
    made = []

    def __init__(self, topic, cls, queue_size=None, latch=False):
        self.resolved_name, self.latch, self.looks = "/" + topic.lstrip("/"), latch, 0
        FakePublisher.made.append(self)

    def get_num_connections(self):
        self.looks += 1
        return int(self.connect_after is not None and self.looks >= self.connect_after)


def test_command_publisher_is_latched_and_returned_once_a_subscriber_is_connected(monkeypatch):
    import pytest
    import rospy
    monkeypatch.setattr(rospy, "Publisher", FakePublisher)
    monkeypatch.setattr(FakePublisher, "connect_after", 3)
    pub = waits.command_publisher("arm/command", float, 10.0)
    assert pub.latch and pub.looks == 3
    monkeypatch.setattr(FakePublisher, "connect_after", None)
    start = time.monotonic()
    with pytest.raises(rospy.ROSException, match=r"nobody subscribed to /arm/command within 0 s"):
        waits.command_publisher("arm/command", float, 0.2)
    assert time.monotonic() - start >= 0.2 and FakePublisher.made[-1].looks > 1


def test_stop_following_clock_drops_rospys_clock_subscription_once(monkeypatch):
    from rospy.impl import simtime
    dropped = []
    sub = type("Sub", (), {"unregister": lambda self: dropped.append(1)})()
    monkeypatch.setattr(simtime, "_clock_sub", sub, raising=False)
    assert waits.stop_following_clock() is True
    assert dropped == [1] and simtime._clock_sub is None
    assert waits.stop_following_clock() is False and dropped == [1]


class FakeMaster(object):
    """rosgraph.Master's two calls GraphWait makes; ``state`` is (publishers, subscribers, services)."""

    def __init__(self):
        self.up = False
        self.state = ([], [], [])

    def getPid(self):
        if not self.up:
            raise OSError("connection refused")
        return 1

    def getSystemState(self):
        if not self.up:
            raise OSError("connection refused")
        return self.state


class FakeSub(object):
    def __init__(self, callback):
        self.callback = callback
        self.unregistered = False

    def unregister(self):
        self.unregistered = True


def test_graph_wait_needs_the_service_advertised_and_a_message_on_the_topic():
    master, subs = FakeMaster(), {}
    graph = waits.GraphWait(master, lambda topic, cb: subs.setdefault(topic, FakeSub(cb)))
    assert not graph.master_up()
    assert graph.pending(["/clock", "/gazebo/spawn"]) == ["/clock", "/gazebo/spawn"]
    master.up = True
    assert graph.master_up()
    master.state = ([("/clock", ["/gazebo"])], [], [("/gazebo/spawn", ["/gazebo"])])
    assert graph.pending(["/clock", "/gazebo/spawn"]) == ["/clock"]  # published, nothing received yet
    assert graph.kind("/clock") == "topic" and list(subs) == ["/clock"]
    subs["/clock"].callback(object())
    assert graph.pending(["/clock", "/gazebo/spawn"]) == []
    graph.close()
    assert subs["/clock"].unregistered


def test_wait_for_graph_says_when_there_is_no_master(monkeypatch):
    monkeypatch.setenv("ROS_MASTER_URI", "http://localhost:1")
    said = []
    start = time.monotonic()
    assert waits.wait_for_graph(["/clock"], 0.3, log=said.append) == 1
    assert time.monotonic() - start >= 0.3
    assert "no ROS master at http://localhost:1" in said[0] and "roslaunch" in said[0]


def test_subscribed_needs_a_subscriber_connected_to_the_topic():
    master = FakeMaster()
    info = {}
    graph = waits.GraphWait(master, None, bus_info=lambda node: info[node])
    topic = "/ptrz/pan_position_controller/state"
    assert graph.unsubscribed([topic]) == [topic]  # no master
    master.up = True
    master.state = ([(topic, ["/gazebo"])], [], [])
    assert graph.unsubscribed([topic]) == [topic]  # published, nobody subscribes
    master.state = ([(topic, ["/gazebo"])], [(topic, ["/rqt_plot_1"]), ("/clock", ["/rec"])], [])
    info["/rec"] = [[1, "/gazebo", "i", "TCPROS", "/clock", True, ""]]
    info["/rqt_plot_1"] = []
    assert graph.unsubscribed([topic]) == [topic]  # registered, not connected yet
    info["/rqt_plot_1"] = [[2, "/gazebo", "i", "TCPROS", topic, False, ""]]
    assert graph.unsubscribed([topic]) == [topic]  # connection not up
    info["/rqt_plot_1"] = [[2, "/gazebo", "o", "TCPROS", topic, True, ""]]
    assert graph.unsubscribed([topic]) == [topic]  # an outgoing one is not a subscription
    del info["/rqt_plot_1"]
    assert graph.unsubscribed([topic]) == [topic]  # a node that does not answer
    info["/rqt_plot_1"] = [[2, "/gazebo", "i", "TCPROS", topic, True, ""]]
    assert graph.unsubscribed([topic, "/clock"]) == []


def test_result_time_is_the_stamp_of_the_result_the_client_received():
    import types
    import pytest
    import rospy
    from actionlib_msgs.msg import GoalStatus
    from control_msgs.msg import FollowJointTrajectoryActionResult
    result = FollowJointTrajectoryActionResult()
    result.header.stamp = rospy.Time(12, 500000000)
    result.status.status = GoalStatus.SUCCEEDED
    machine = types.SimpleNamespace(latest_result=result)
    client = types.SimpleNamespace(gh=types.SimpleNamespace(comm_state_machine=machine),
                                   action_client=types.SimpleNamespace(ns="/arm/follow_joint_trajectory"))
    assert waits.result_time(client) == 12.5
    machine.latest_result = None
    with pytest.raises(ValueError, match="/arm/follow_joint_trajectory"):
        waits.result_time(client)
    client.gh = None
    with pytest.raises(ValueError, match="wait_for_result first"):
        waits.result_time(client)


class FakeSubscriber(object):
    def __init__(self, topic, cls, callback, queue_size=None, buff_size=None):
        self.topic, self.callback, self.queue_size, self.buff_size = topic, callback, queue_size, buff_size


def test_latest_keeps_messages_with_their_receipt_times_and_finds_one_by_stamp(monkeypatch):
    import rospy
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Float64
    monkeypatch.setattr(waits.rospy, "Subscriber", FakeSubscriber)
    now = [10.0]
    monkeypatch.setattr(waits.rospy, "get_time", lambda: now[0])
    commands = waits.Latest("/pan/command", Float64, keep=True)
    assert commands.sub.queue_size is None            # every message, unless asked otherwise
    for t, v in ((10.5, 0.1), (10.6, 0.2)):
        now[0] = t
        commands.sub.callback(Float64(v))
    assert [(t, m.data) for t, m in commands.received] == [(10.5, 0.1), (10.6, 0.2)]
    assert commands.msg.data == 0.2 and commands.count == 2
    commands.clear()
    assert commands.received == [] and commands.history == []
    images = waits.Latest("/camera/image_raw", JointState, queue_size=1, buff_size=2 ** 24)
    assert (images.sub.queue_size, images.sub.buff_size) == (1, 2 ** 24)
    import pytest
    with pytest.raises(ValueError, match="keep=True"):
        images.received
    states = waits.Latest("/joint_states", JointState, keep=True)
    for stamp in (1.0, 1.02, 1.04):
        m = JointState()
        m.header.stamp = rospy.Time.from_sec(stamp)
        states.sub.callback(m)
    assert states.after(1.01, timeout=0.1).header.stamp.to_sec() == 1.02   # the first that young
    with pytest.raises(AssertionError, match="simulated time 2.000 or later"):
        states.after(2.0, timeout=0.1)
    with pytest.raises(TypeError, match="no header stamp"):
        commands.after(1.0)


def test_wait_for_result_is_limited_in_wall_time_and_needs_a_goal():
    import types
    import pytest
    from actionlib import SimpleGoalState
    looks = []

    class Client(object):
        gh = object()
        action_client = types.SimpleNamespace(ns="/gripper_cmd")

        @property
        def simple_state(self):
            looks.append(1)
            return SimpleGoalState.DONE if len(looks) > 3 else SimpleGoalState.ACTIVE
    assert waits.wait_for_result(Client(), 10.0) and len(looks) == 4
    start = time.monotonic()
    stuck = types.SimpleNamespace(gh=object(), simple_state=SimpleGoalState.ACTIVE,
                                  action_client=types.SimpleNamespace(ns="/arm"))
    assert not waits.wait_for_result(stuck, 0.2)
    assert time.monotonic() - start >= 0.2
    with pytest.raises(ValueError, match="send_goal first"):
        waits.wait_for_result(types.SimpleNamespace(gh=None, action_client=stuck.action_client), 1.0)

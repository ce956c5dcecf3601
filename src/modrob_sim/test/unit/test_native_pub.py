"""Tier 1 (own roscore on a free port): the roscpp publishers of the /gazebo node's process
(modrob_sim.gazebo_ros.native_pub, libmodrob_roscpp_pub.so) send exactly the bytes rospy sends
(header seq included), latch, count their subscribers, are registered by the ``<node>_roscpp``
node, and without roscpp started the publishers are rospy's. /clock from a ClockTicker (the World's
native steps through its step observer, deferred until ``flush``) reaches every subscriber complete
and in order as rospy's bytes, mixed with immediate messages, also one that comes and goes
mid-stream; a late subscriber of the latched topic gets the last message alone, and one that comes
while the topic flows never gets an older message after a newer one; a stalled
subscriber blocks nothing; the ticker's wall-clock period and its one message per simulated time
hold."""
import os
import signal
import socket
import subprocess
import sys
import textwrap
import time

import pytest

pytestmark = pytest.mark.skipif(not os.path.exists("/usr/bin/roscore"), reason="needs ROS")

# runs as a ROS node in its own process (this pytest process must not become one)
CLIENT = textwrap.dedent(r"""
    import io, sys, time
    import rospy, rosgraph
    from rospy.msg import serialize_message
    from sensor_msgs.msg import JointState
    from rosgraph_msgs.msg import Clock
    from modrob_sim.gazebo_ros import native_pub

    rospy.init_node("pubtest", disable_signals=True)
    native = native_pub.start(rospy.get_name()) if sys.argv[1] == "roscpp" else False
    print("native", native, native_pub.reason(), flush=True)
    js_pub = native_pub.publisher("~joint_states", JointState, queue_size=10)
    clock_pub = native_pub.publisher("/clock_test", Clock, queue_size=10, latch=True)
    print("class", type(js_pub).__name__, js_pub.resolved_name, flush=True)

    def expected(msg, seq):
        b = io.BytesIO()
        serialize_message(b, seq, msg)
        return b.getvalue()[4:]

    clock = Clock()
    clock.clock.secs, clock.clock.nsecs = 12, 345
    clock_pub.publish(clock)                      # before anyone subscribes: latched
    got = {"js": [], "clock": []}
    subs = [rospy.Subscriber(js_pub.resolved_name, rospy.AnyMsg, lambda m: got["js"].append(m._buff)),
            rospy.Subscriber("/clock_test", rospy.AnyMsg, lambda m: got["clock"].append(m._buff))]
    deadline = time.time() + 30
    while js_pub.get_num_connections() == 0 and time.time() < deadline:
        time.sleep(0.05)
    print("connections", js_pub.get_num_connections(), flush=True)
    msgs = []
    for k in range(3):
        m = JointState(name=["a", "b"], position=[0.5 * k, -1.25], velocity=[1e-3, 2.0], effort=[])
        m.header.stamp = rospy.Time(3, 14 + k)
        m.header.frame_id = "base"
        msgs.append(m)
        js_pub.publish(m)
    if native:      # bytes already serialised in a ctypes buffer (the states of native_states)
        import ctypes
        raw = expected(msgs[0], 7)
        buf = (ctypes.c_uint8 * (len(raw) + 5)).from_buffer_copy(raw + b"extra")
        js_pub.publish_serialized(buf, len(raw))
        msgs.append(None)
    while (len(got["js"]) < len(msgs) or not got["clock"]) and time.time() < deadline:
        time.sleep(0.05)
    print("js_equal", [bytes(a) == expected(m, i + 1) for i, (a, m) in enumerate(zip(got["js"], msgs[:3]))],
          flush=True)
    print("serialized_equal", native and len(got["js"]) == 4 and bytes(got["js"][3]) == raw, flush=True)
    print("clock_equal", bool(got["clock"]) and bytes(got["clock"][0]) == expected(clock, 1), flush=True)
    state = rosgraph.Master("/pubtest").getSystemState()[0]
    print("publishers", dict((t, n) for t, n in state)[js_pub.resolved_name], flush=True)
    for s in subs:
        s.unregister()
    native_pub.stop()
""")


# a subscriber in its own process (its own connection): takes the first int(argv[1]) /clock_deferred
# messages, or what comes in 0.5 s after the first, leaves and prints them (their whole seconds)
LISTEN = textwrap.dedent(r"""
    import struct, sys, threading, time
    import rospy
    rospy.init_node("listen", anonymous=True, disable_signals=True)
    most, got, done = int(sys.argv[1]), [], threading.Event()

    def cb(m):
        if len(got) < most:
            secs, nsecs = struct.unpack("<2I", bytes(m._buff))
            got.append(secs)
        if len(got) >= most:
            done.set()
    sub = rospy.Subscriber("/clock_deferred", rospy.AnyMsg, cb)
    deadline = time.time() + 60
    while not got and time.time() < deadline:
        time.sleep(0.01)
    done.wait(0.5 if most > 10 ** 6 else 60)
    sub.unregister()
    print(" ".join(str(v) for v in got), flush=True)
""")

# /clock through a ClockTicker, as the World's native steps (its observer) and the node's after-step
# hook tick it and the node's passes flush it; whole seconds as times, so that the bytes say which
DEFERRED = textwrap.dedent(r"""
    LISTEN = LISTEN_SOURCE
    import io, struct, subprocess, sys, threading, time
    import rospy
    from rospy.msg import serialize_message
    from rosgraph_msgs.msg import Clock
    from modrob_sim.gazebo_ros import native_pub

    rospy.init_node("deftest", disable_signals=True)
    assert native_pub.start(rospy.get_name()), native_pub.reason()
    pub = native_pub.publisher("/clock_deferred", Clock, queue_size=10, latch=True)
    ticker = pub.clock_ticker(0.0)

    def secs(buf):
        return struct.unpack("<2I", bytes(buf))[0]

    def wait(pred, limit=30.0):
        deadline = time.time() + limit
        while not pred() and time.time() < deadline:
            time.sleep(0.01)
        return pred()

    full, raw = [], []
    subs = [rospy.Subscriber("/clock_deferred", rospy.AnyMsg,
                             lambda m: (full.append(secs(m._buff)), raw.append(bytes(m._buff))))]
    wait(lambda: pub.get_num_connections() == 1)
    N, BATCH = 3000, 10
    mid, left = None, None
    k = 0
    while k < N:
        if left is None and k >= 2 * N // 3:      # it has had its 800: publishing goes on without it
            left = wait(lambda: pub.get_num_connections() == 1)
        if mid is None and k >= N // 3:           # a subscriber that comes, takes 800 and goes
            mid = subprocess.Popen([sys.executable, "-c", LISTEN, "800"], stdout=subprocess.PIPE, text=True)
            wait(lambda: pub.get_num_connections() == 2)
        if k % 70 == 0:                           # an immediate message between deferred ones
            c = Clock()
            c.clock.secs = k
            pub.publish(c)
            k += 1
            continue
        for j in range(k, min(k + BATCH, N)):
            if j % 70 == 35:                      # immediate, while deferred ones wait: they go first
                c = Clock()
                c.clock.secs = j
                pub.publish(c)
            else:
                ticker.tick(float(j))
                ticker.tick(float(j))             # one message per simulated time
        k = min(k + BATCH, N)
        pub.flush()
        # paced by the subscriber (a connection's queue holds 10: one that lags on a loaded machine
        # loses messages, as ROS documents); what is tested is order and completeness, not speed
        wait(lambda: len(full) >= k - BATCH)
    mid_out = mid.communicate(timeout=60)[0].split()
    print("mid_left_before_the_end", left, flush=True)
    print("mid_consecutive", mid_out == [str(v) for v in range(int(mid_out[0]), int(mid_out[0]) + 800)],
          flush=True)
    wait(lambda: len(full) >= N)
    print("full_in_order", full == list(range(N)), len(full), flush=True)

    from modrob_sim.gazebo_ros.state_publishers import set_clock

    def rospy_bytes(t):                           # what the node's rospy path sends for t
        b = io.BytesIO()
        serialize_message(b, 0, set_clock(Clock(), t))
        return b.getvalue()[4:]
    print("rospys_bytes", all(raw[j] == rospy_bytes(float(j)) for j in range(N)), flush=True)
    late = subprocess.run([sys.executable, "-c", LISTEN, str(10 ** 9)], capture_output=True, text=True,
                          timeout=90).stdout.split()
    print("late", late, flush=True)
    # the nanoseconds as rospy rounds them, and the wall-clock period
    frac = native_pub.publisher("/clock_frac", Clock, queue_size=10)
    fr = []
    subs.append(rospy.Subscriber("/clock_frac", rospy.AnyMsg, lambda m: fr.append(bytes(m._buff))))
    wait(lambda: frac.get_num_connections() == 1)
    tf = frac.clock_ticker(0.0)
    times = [6.9895, 7.0 - 1e-10, 1e-3 * 7, 12345.678901234]
    for t in times:
        tf.tick(t)
    frac.flush()
    wait(lambda: len(fr) == len(times))
    print("fractions", fr == [rospy_bytes(t) for t in times], flush=True)
    slow = frac.clock_ticker(0.05)
    t0, sent = time.monotonic(), 0
    while time.monotonic() - t0 < 0.5:
        sent += slow.tick(time.monotonic())
    print("throttled", sent, flush=True)

    # a stalled subscriber: its socket fills up; publishing goes on (roscpp drops its oldest queued)
    big = native_pub.publisher("/big_deferred", Clock, queue_size=10)
    big_ticker = big.clock_ticker(0.0)
    release = threading.Event()
    got = []

    def stalled(m):
        got.append(secs(m._buff))
        release.wait(60)

    subs.append(rospy.Subscriber("/big_deferred", rospy.AnyMsg, stalled))
    wait(lambda: big.get_num_connections() == 1)
    M = 400000                                    # 4.8 MB: more than the sockets' buffers hold
    done = threading.Event()

    def run():
        for i in range(M):
            big_ticker.tick(float(i))
            if i % 1000 == 999:
                big.flush()
        big.flush()
        done.set()
    threading.Thread(target=run, daemon=True).start()
    print("stalled_not_blocking", done.wait(120), flush=True)
    release.set()
    wait(lambda: got and got[-1] == M - 1)
    print("stalled_in_order", all(a < b for a, b in zip(got, got[1:])), got[-1] == M - 1, len(got) < M,
          flush=True)
    for s in subs:
        s.unregister()
    native_pub.stop()
""").replace("LISTEN_SOURCE", repr(LISTEN))


# the subscriber counts as the subscribers come and go: a subscriber in another process (rospy
# shares one connection per topic and process), a second publisher of the same topic in this
# process (roscpp's one publication of the topic: the same count), a publisher that leaves while
# the other stays, and none once roscpp stops
COUNTS = textwrap.dedent(r"""
    import subprocess, sys, time
    import rospy
    from sensor_msgs.msg import JointState
    from modrob_sim.gazebo_ros import native_pub

    rospy.init_node("counttest", disable_signals=True)
    assert native_pub.start(rospy.get_name()), native_pub.reason()
    a = native_pub.publisher("/counted", JointState, queue_size=10)
    b = native_pub.publisher("/counted", JointState, queue_size=10)
    other = native_pub.publisher("/not_counted", JointState, queue_size=10)

    def settle(pub, n):
        deadline = time.time() + 30
        while pub.get_num_connections() != n and time.time() < deadline:
            time.sleep(0.02)
        return pub.get_num_connections()

    SUB = "import rospy, sys; rospy.init_node('s', anonymous=True); " \
          "rospy.Subscriber('/counted', rospy.AnyMsg, lambda m: None); sys.stdin.read()"
    print("none", a.get_num_connections(), b.get_num_connections(), flush=True)
    procs = [subprocess.Popen([sys.executable, "-c", SUB], stdin=subprocess.PIPE)]
    print("one", settle(a, 1), b.get_num_connections(), other.get_num_connections(), flush=True)
    procs.append(subprocess.Popen([sys.executable, "-c", SUB], stdin=subprocess.PIPE))
    print("two", settle(a, 2), b.get_num_connections(), flush=True)
    procs.pop().communicate(timeout=30)
    print("back_to_one", settle(a, 1), b.get_num_connections(), flush=True)
    a.unregister()
    print("after_unregister", a.get_num_connections(), b.get_num_connections(), flush=True)
    procs.pop().communicate(timeout=30)
    print("gone", settle(b, 0), flush=True)
    procs.append(subprocess.Popen([sys.executable, "-c", SUB], stdin=subprocess.PIPE))
    print("again", settle(b, 1), flush=True)
    native_pub.stop()
    print("stopped", b.get_num_connections(), flush=True)
    procs.pop().communicate(timeout=30)
""")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def master():
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:%d" % port)
    core = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.time() + 30
        while subprocess.run(["rosnode", "list"], env=env, capture_output=True).returncode != 0:
            assert time.time() < deadline, "roscore did not come up"
            time.sleep(0.2)
        yield env
    finally:
        os.killpg(core.pid, signal.SIGINT)
        core.wait(30)


def run_client(env, mode="roscpp"):
    proc = subprocess.run([sys.executable, "-c", CLIENT, mode], env=env, capture_output=True, text=True,
                          timeout=90)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return dict(ln.split(" ", 1) for ln in proc.stdout.splitlines() if " " in ln)


def test_roscpp_publishers_send_rospys_bytes_and_latch(master):
    out = run_client(master)
    assert out["native"].startswith("True"), out["native"]
    assert out["class"] == "NativePublisher /pubtest/joint_states"
    assert out["connections"] == "1"
    assert out["js_equal"] == "[True, True, True]"
    assert out["serialized_equal"] == "True"
    assert out["clock_equal"] == "True"
    assert out["publishers"] == "['/pubtest_roscpp']"


def test_subscriber_counts_follow_the_subscribers(master):
    proc = subprocess.run([sys.executable, "-c", COUNTS], env=master, capture_output=True, text=True,
                          timeout=180)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = dict(ln.split(" ", 1) for ln in proc.stdout.splitlines() if " " in ln)
    assert out["none"] == "0 0"
    assert out["one"] == "1 1 0"
    assert out["two"] == "2 2"
    assert out["back_to_one"] == "1 1"
    assert out["after_unregister"] == "0 1"     # a's handle is gone; b keeps the topic and its subscriber
    assert out["gone"] == "0"
    assert out["again"] == "1"
    assert out["stopped"] == "0"


def test_without_roscpp_it_is_rospy(master):
    out = run_client(master, mode="rospy")      # the node's ~native_publishing false: not started
    assert out["native"] == "False not started"
    assert out["class"] == "Publisher /pubtest/joint_states"
    assert out["js_equal"] == "[True, True, True]"
    assert out["clock_equal"] == "True"
    assert out["publishers"] == "['/pubtest']"


def test_deferred_messages_arrive_complete_in_order_and_latch_the_last(master):
    proc = subprocess.run([sys.executable, "-c", DEFERRED], env=master, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = dict(ln.split(" ", 1) for ln in proc.stdout.splitlines() if " " in ln)
    assert out["full_in_order"] == "True 3000", out
    assert out["rospys_bytes"] == "True", out
    assert out["fractions"] == "True", out
    assert 8 <= int(out["throttled"]) <= 11, out       # 0.5 s at one per 50 ms
    # the subscriber that came mid-stream got 800 consecutive messages and left before the end
    assert out["mid_consecutive"] == "True", out
    assert out["mid_left_before_the_end"] == "True", out
    assert out["late"] == "['2999']", out
    assert out["stalled_not_blocking"] == "True", out
    # what the stalled subscriber got is in order and ends with the last message; the rest was dropped
    # on its full connection, not waited for
    assert out["stalled_in_order"] == "True True True", out


# a latched /clock ticked as fast as it goes (deferred, flushed every 3 ticks, as the node's passes
# do) while subscribers come one after another, each reading its first 20 messages; then, with the
# clock stopped (a paused simulation), one more subscriber
COMERS = textwrap.dedent(r"""
    import sys, threading, time
    import rospy
    from rosgraph_msgs.msg import Clock
    from modrob_sim.gazebo_ros import native_pub

    rospy.init_node("comers", disable_signals=True)
    assert native_pub.start(rospy.get_name()), native_pub.reason()
    pub = native_pub.publisher("/clock_comers", Clock, queue_size=10, latch=True)
    ticker = pub.clock_ticker(0.0)
    stop = threading.Event()

    def run():
        t, n = 0.0, 0
        while not stop.is_set():
            t, n = t + 0.001, n + 1
            ticker.tick(t)
            if n % 3 == 0:
                pub.flush()
            if n % 30 == 0:
                time.sleep(0.0005)
        pub.flush()
    runner = threading.Thread(target=run, daemon=True)
    runner.start()

    def first(count):
        got, done = [], threading.Event()

        def cb(m):
            got.append(m.clock.to_sec())
            if len(got) >= count:
                done.set()
        sub = rospy.Subscriber("/clock_comers", Clock, cb, queue_size=100)
        done.wait(10)
        sub.unregister()
        return list(got)
    back = []
    for r in range(int(sys.argv[1])):
        got = first(20)
        assert len(got) >= 20, got
        if any(b < a for a, b in zip(got, got[1:])):
            back.append(["%.3f" % v for v in got[:5]])
    print("backwards", back, flush=True)
    stop.set()
    runner.join()
    got = first(1)
    print("paused", len(got) == 1 and abs(got[0] - ticker.last) < 1e-6, flush=True)
    # the topic says it is latched: a second subscription of this process (rospy shares the
    # connection) gets rospy's copy of the connection's last message at once
    one, two = [], []
    keep = rospy.Subscriber("/clock_comers", Clock, lambda m: one.append(m.clock.to_sec()))
    deadline = time.time() + 10
    while not one and time.time() < deadline:
        time.sleep(0.01)
    second = rospy.Subscriber("/clock_comers", Clock, lambda m: two.append(m.clock.to_sec()))
    print("second", bool(one) and two == one[-1:], flush=True)
    keep.unregister()
    second.unregister()
    native_pub.stop()
""")


def test_a_subscriber_that_comes_while_the_latched_clock_flows_never_sees_it_go_back(master):
    """roscpp's own latch handed a new subscriber the newest message while older ones still waited
    in the publication's queue: 8 of 200 subscribers saw /clock go back (and a rospy Timer that sees
    that dies). A late subscriber of the stopped clock still gets the last message, and a second
    subscription of its process gets rospy's copy of it (the topic says it is latched)."""
    proc = subprocess.run([sys.executable, "-c", COMERS, "150"], env=master, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = dict(ln.split(" ", 1) for ln in proc.stdout.splitlines() if " " in ln)
    assert out["backwards"] == "[]", out
    assert out["paused"] == "True", out
    assert out["second"] == "True", out


def test_the_clock_ticks_in_the_after_hook_and_flushes_after_a_pass():
    """StatePublishers gives the World the ticker's observer, ticks /clock in its after-step hook
    (the ticker sends it once per time: the observer may have sent the step's already) and sends it
    at once, before anything the step publishes; after the loop's pass it flushes before the scene."""
    import types
    from modrob_sim.gazebo_ros.state_publishers import StatePublishers
    calls = []

    class Ticker(object):
        observer = (1234, 5678)

        def tick(self, t):
            calls.append(("tick", t))

    class ClockPub(object):
        def clock_ticker(self, period):
            calls.append(("ticker", period))
            return Ticker()

        def flush(self):
            calls.append(("flush",))

    out = StatePublishers.__new__(StatePublishers)
    world = types.SimpleNamespace(time=1.5, time_step=0.001,
                                  set_step_observer=lambda fn, user: calls.append(("observer", fn, user)))
    out.world = world
    out._clock_pub = ClockPub()
    out._clock_period, out._last_clock_wall = 0.0, -1e9
    out._ticker = out._clock_pub.clock_ticker(0.0)
    world.set_step_observer(*out._ticker.observer)
    out._scene = types.SimpleNamespace(after_step=lambda t: calls.append(("scene", t)))
    out._next_state_t = out._next_marker_t = 10.0
    out._state_period = out._marker_period = 0.01
    out.after_step()
    out.after_pass()
    assert calls == [("ticker", 0.0), ("observer", 1234, 5678), ("tick", 1.5), ("flush",), ("scene", 1.5),
                     ("flush",), ("scene", 1.5)]
    # /clock needs no Python step; the states and markers are due by their periods' last steps
    assert out.after_due() == pytest.approx(10.0 + 0.009 - 0.0005)


# thirty latched topics ticked as fast as they go (as /clock) and one latched topic sent once: a
# process subscribes to all of them at once and measures how soon the quiet topic's last message
# comes (the publisher's connect callbacks share one thread)
CROWD = textwrap.dedent(r"""
    import threading, time
    import rospy
    from rosgraph_msgs.msg import Clock
    from std_msgs.msg import String
    from modrob_sim.gazebo_ros import native_pub

    rospy.init_node("crowd", disable_signals=True)
    assert native_pub.start(rospy.get_name()), native_pub.reason()
    busy = [native_pub.publisher("/busy_%d" % k, Clock, queue_size=10, latch=True) for k in range(30)]
    quiet = native_pub.publisher("/quiet", String, queue_size=1, latch=True)
    quiet.publish(String("sent once"))
    stop = threading.Event()

    def run():
        t = 0.0
        while not stop.is_set():
            t += 0.001
            for p in busy:
                p.publish(Clock(clock=rospy.Time.from_sec(t)))
            time.sleep(0.001)
    threading.Thread(target=run, daemon=True).start()
    time.sleep(1.0)                         # the quiet topic has been quiet for a while
    got = threading.Event()
    subs = [rospy.Subscriber("/busy_%d" % k, Clock, lambda m: None) for k in range(30)]
    t0 = time.monotonic()
    subs.append(rospy.Subscriber("/quiet", String, lambda m: got.set()))
    got.wait(20)
    print("quiet_after %.3f" % (time.monotonic() - t0 if got.is_set() else -1), flush=True)
    stop.set()
    native_pub.stop()
""")


def test_a_latched_topic_reaches_its_subscriber_while_others_flow(master):
    """A new subscriber's connect callback waits until the topic has been quiet for a moment before
    it replays the last message; it used to sleep that moment out whole, holding up the connect
    callbacks of every other topic: a renderer's RViz then got the scene's markers seconds late, behind
    the subscribers of /clock (here 1.8-3.4 s with 20 flowing topics; 0.03-0.06 s since)."""
    proc = subprocess.run([sys.executable, "-c", CROWD], env=master, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = dict(ln.split(" ", 1) for ln in proc.stdout.splitlines() if " " in ln)
    assert 0.0 <= float(out["quiet_after"]) < 0.75, out

"""Tier 1 (own roscore on a free port): the roscpp publishers of the /gazebo node's process
(modrob_sim.gazebo_ros.native_pub, libmodrob_roscpp_pub.so) send exactly the bytes rospy sends
(header seq included), latch, count their subscribers, are registered by the ``<node>_roscpp``
node, and MODROB_SIM_ROSCPP=0 falls back to rospy publishers. Messages deferred by C code (the C loop's
/clock in a batch of steps: ``native_handle(deferred=True)``, then ``flush``) reach every subscriber
complete and in order, mixed with immediate ones, also one that comes and goes mid-stream; a late
subscriber of the latched topic gets the last message alone; a stalled subscriber blocks nothing."""
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
    native = native_pub.start(rospy.get_name())
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
    while (len(got["js"]) < 3 or not got["clock"]) and time.time() < deadline:
        time.sleep(0.05)
    print("js_equal", [bytes(a) == expected(m, i + 1) for i, (a, m) in enumerate(zip(got["js"], msgs))],
          flush=True)
    print("clock_equal", bool(got["clock"]) and bytes(got["clock"][0]) == expected(clock, 1), flush=True)
    state = rosgraph.Master("/pubtest").getSystemState()[0]
    print("publishers", dict((t, n) for t, n in state)[js_pub.resolved_name], flush=True)
    for s in subs:
        s.unregister()
    native_pub.stop()
""")


# a subscriber in its own process (its own connection): takes the first int(argv[1]) /clock_deferred
# messages, or what comes in 0.5 s after the first, leaves and prints them (as ms)
LISTEN = textwrap.dedent(r"""
    import struct, sys, threading, time
    import rospy
    rospy.init_node("listen", anonymous=True, disable_signals=True)
    most, got, done = int(sys.argv[1]), [], threading.Event()

    def cb(m):
        if len(got) < most:
            secs, nsecs = struct.unpack("<2I", bytes(m._buff))
            got.append(secs * 1000 + nsecs // 1000000)
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

# deferred publishing, as the C loop and StatePublishers.after_batch do it
DEFERRED = textwrap.dedent(r"""
    LISTEN = LISTEN_SOURCE
    import ctypes, struct, subprocess, sys, threading, time
    import rospy
    from rosgraph_msgs.msg import Clock
    from std_msgs.msg import String
    from modrob_sim.gazebo_ros import native_pub

    rospy.init_node("deftest", disable_signals=True)
    assert native_pub.start(rospy.get_name()), native_pub.reason()
    PUBLISH = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_char_p, ctypes.c_uint32)
    pub = native_pub.publisher("/clock_deferred", Clock, queue_size=10, latch=True)
    addr, handle = pub.native_handle(deferred=True)
    deferred = PUBLISH(addr)

    def ms(buf):                                  # a Clock's bytes -> its time in ms
        secs, nsecs = struct.unpack("<2I", bytes(buf))
        return secs * 1000 + nsecs // 1000000

    def wait(pred, limit=30.0):
        deadline = time.time() + limit
        while not pred() and time.time() < deadline:
            time.sleep(0.01)
        return pred()

    full = []
    subs = [rospy.Subscriber("/clock_deferred", rospy.AnyMsg, lambda m: full.append(ms(m._buff)))]
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
            c.clock.secs, c.clock.nsecs = k // 1000, (k % 1000) * 1000000
            pub.publish(c)
            k += 1
            continue
        for j in range(k, min(k + BATCH, N)):
            if j % 70 == 35:                      # immediate, while deferred ones wait: they go first
                c = Clock()
                c.clock.secs, c.clock.nsecs = j // 1000, (j % 1000) * 1000000
                pub.publish(c)
            else:
                deferred(handle, struct.pack("<2I", j // 1000, (j % 1000) * 1000000), 8)
        k = min(k + BATCH, N)
        pub.flush()
        time.sleep(0.001)
    mid_out = mid.communicate(timeout=60)[0].split()
    print("mid_left_before_the_end", left, flush=True)
    print("mid_consecutive", mid_out == [str(v) for v in range(int(mid_out[0]), int(mid_out[0]) + 800)],
          flush=True)
    wait(lambda: len(full) >= N)
    print("full_in_order", full == list(range(N)), len(full), flush=True)
    late = subprocess.run([sys.executable, "-c", LISTEN, str(10 ** 9)], capture_output=True, text=True,
                          timeout=90).stdout.split()
    print("late", late, flush=True)

    # a stalled subscriber: its socket fills up; publishing goes on (roscpp drops its oldest queued)
    big = native_pub.publisher("/big_deferred", String, queue_size=10)
    addr, big_handle = big.native_handle(deferred=True)
    release = threading.Event()
    got = []

    def stalled(m):
        got.append(int(bytes(m._buff)[4:12]))
        release.wait(60)

    subs.append(rospy.Subscriber("/big_deferred", rospy.AnyMsg, stalled))
    wait(lambda: big.get_num_connections() == 1)
    M, PAD = 20000, b"x" * 2000                   # 40 MB: more than the sockets' buffers hold
    done = threading.Event()

    def run():
        for i in range(M):
            body = b"%08d" % i + PAD
            PUBLISH(addr)(big_handle, struct.pack("<I", len(body)) + body, 4 + len(body))
            if i % BATCH == BATCH - 1:
                big.flush()
        big.flush()
        done.set()
    t0 = time.time()
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


def run_client(env):
    proc = subprocess.run([sys.executable, "-c", CLIENT], env=env, capture_output=True, text=True, timeout=90)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return dict(ln.split(" ", 1) for ln in proc.stdout.splitlines() if " " in ln)


def test_roscpp_publishers_send_rospys_bytes_and_latch(master):
    out = run_client(master)
    assert out["native"].startswith("True"), out["native"]
    assert out["class"] == "NativePublisher /pubtest/joint_states"
    assert out["connections"] == "1"
    assert out["js_equal"] == "[True, True, True]"
    assert out["clock_equal"] == "True"
    assert out["publishers"] == "['/pubtest_roscpp']"


def test_switched_off_it_is_rospy(master):
    out = run_client(dict(master, MODROB_SIM_ROSCPP="0"))
    assert out["native"] == "False disabled by MODROB_SIM_ROSCPP=0"
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
    # the subscriber that came mid-stream got 800 consecutive messages and left before the end
    assert out["mid_consecutive"] == "True", out
    assert out["mid_left_before_the_end"] == "True", out
    assert out["late"] == "['2999']", out
    assert out["stalled_not_blocking"] == "True", out
    # what the stalled subscriber got is in order and ends with the last message; the rest was dropped
    # on its full connection, not waited for
    assert out["stalled_in_order"] == "True True True", out


def test_a_batchs_clock_is_deferred_and_flushed_when_the_batch_ends():
    """StatePublishers hands the C loop the deferred entry point for /clock and flushes after the
    batch (gazebo_ros.fast_steps calls after_batch after every batch), before anything else."""
    import types
    from modrob_sim.gazebo_ros.state_publishers import StatePublishers
    calls = []

    class ClockPub(object):
        def native_handle(self, deferred=False):
            calls.append(("handle", deferred))
            return (1234, 5678)

        def flush(self):
            calls.append(("flush",))

    out = StatePublishers.__new__(StatePublishers)
    out.world = types.SimpleNamespace(time=1.5)
    out._clock_pub = ClockPub()
    out._clock_period, out._last_clock_wall, out._batch_clock, out._clock_sent_t = 0.0, -1e9, None, None
    out._scene = types.SimpleNamespace(after_step=lambda t: calls.append(("scene", t)))
    clock = out.batch_clock()
    assert (clock.publish, clock.handle, clock.period) == (1234, 5678, 0.0)
    clock.sent = True
    out.after_batch()
    assert calls == [("handle", True), ("flush",), ("scene", 1.5)]
    assert out._clock_sent_t == 1.5

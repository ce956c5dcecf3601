"""Tier 1 (own roscore on a free port): the roscpp publishers of the /gazebo node's process
(modrob_sim.gazebo_ros.native_pub, libmodrob_roscpp_pub.so) send exactly the bytes rospy sends
(header seq included), latch, count their subscribers, are registered by the ``<node>_roscpp``
node, and MODROB_SIM_ROSCPP=0 falls back to rospy publishers."""
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

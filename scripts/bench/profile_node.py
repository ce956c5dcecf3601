#!/usr/bin/env python3
"""Profile the full /gazebo node on the benchmark scene (6-DoF arm with effort PID controllers and
joint_state_controller, table, 5 cans; real_time_factor 0; /clock, states and joint_states
subscribed) with py-spy (every thread, sampled), and print where its CPU goes.

    source scripts/env.sh; scripts/bench/.venv-bench/bin/python scripts/bench/profile_node.py \
        [--seconds 10] [--clock-hz 0]      (py-spy: requirements-bench.txt, installed by run.sh)

Writes out/bench/profile_node.collapsed (flame-graph input) and prints the top functions by
inclusive and by own samples, per thread.
"""
import argparse
import collections
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import units  # noqa: E402


def short(frame):
    """'fn (path/to/file.py:12)' -> 'fn file.py:12'"""
    if " (" not in frame:
        return frame
    return frame.split(" (")[0] + " " + frame.rsplit("/", 1)[-1].rstrip(")")


def summarise(path, top=25):
    incl, own, threads = collections.Counter(), collections.Counter(), collections.Counter()
    total = 0
    with open(path) as f:
        for ln in f:
            stack, _, n = ln.rstrip("\n").rpartition(" ")
            n = int(n)
            frames = stack.split(";")
            total += n
            threads[frames[0]] += n
            seen = set()
            for fr in frames[1:]:
                key = short(fr)
                if key not in seen:
                    incl[key] += n
                    seen.add(key)
            last = frames[-1]
            own[short(last)] += n
    print("samples: %d" % total)
    print("\nper thread:")
    for k, n in threads.most_common():
        print("  %5.1f %%  %s" % (100.0 * n / total, k))
    print("\ninclusive:")
    for k, n in incl.most_common(top):
        print("  %5.1f %%  %s" % (100.0 * n / total, k))
    print("\nown:")
    for k, n in own.most_common(top):
        print("  %5.1f %%  %s" % (100.0 * n / total, k))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--clock-hz", type=float, default=1000.0)
    ap.add_argument("--out", default=os.path.join(units.ROOT, "out", "bench", "profile_node.collapsed"))
    args = ap.parse_args()
    spy = shutil.which("py-spy") or os.path.join(os.path.dirname(sys.executable), "py-spy")
    if not os.path.exists(spy):
        sys.exit("profile_node: py-spy is not installed (pip install py-spy in scripts/bench/.venv-bench)")
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    master = units.Master()
    try:
        import rospy
        from std_srvs.srv import Empty
        from gazebo_msgs.msg import LinkStates, ModelStates
        from rosgraph_msgs.msg import Clock
        from sensor_msgs.msg import JointState
        rospy.set_param("/use_sim_time", True)
        rospy.init_node("bench_profile", disable_signals=True)
        node = units.start_node(["_pub_clock_frequency:=%g" % args.clock_hz])
        try:
            units.build_scene()
            subs = [rospy.Subscriber("/clock", Clock, lambda m: None, queue_size=10),
                    rospy.Subscriber("/gazebo/model_states", ModelStates, lambda m: None, queue_size=1),
                    rospy.Subscriber("/gazebo/link_states", LinkStates, lambda m: None, queue_size=1),
                    rospy.Subscriber("/arm/joint_states", JointState, lambda m: None, queue_size=10)]
            time.sleep(1.0)
            rospy.ServiceProxy("/gazebo/unpause_physics", Empty)()
            time.sleep(0.5)
            c0, t0 = units.cpu_seconds(node.pid), time.monotonic()
            subprocess.run([spy, "record", "-p", str(node.pid), "-d", str(int(args.seconds)), "-r", "250",
                            "--threads", "--nonblocking", "-f", "raw", "-o", args.out],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
            c1, t1 = units.cpu_seconds(node.pid), time.monotonic()
            print("node CPU load during the profile: %.2f cores" % ((c1 - c0) / (t1 - t0)))
            for s in subs:
                s.unregister()
        finally:
            units.terminate(node)
    finally:
        master.close()
    summarise(args.out)


if __name__ == "__main__":
    main()

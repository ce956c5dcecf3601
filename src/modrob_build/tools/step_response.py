#!/usr/bin/env python3
"""Step response of a running generated robot with its default gains (tuned or computed; a check of
the gains; the plot goes into docs/modules.md).

    roslaunch modrob_build urdf_and_gazebo.launch orders:="59,3,55,63,64,4,66,4,67,5,56,5" \
        gripper:=true gui:=false real_time_factor:=0 &
    python3 step_response.py OUT.png [ns] [joint=target ...] [_title:="..."]

Commands every target at once (a hard test: simultaneous large steps), records
/<ns>/joint_states for 6 s of simulated time, prints rise/overshoot/final error per joint and
plots the angles.
"""
import sys
import threading
import time

import matplotlib
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DEFAULT_TARGETS = {"joint1": 0.8, "joint2": 1.2, "joint3": -0.6, "joint4": 1.0, "joint5": 0.7,
                   "joint6": 1.5}
DURATION = 6.0


def main():
    argv = rospy.myargv(sys.argv)
    out = argv[1]
    ns = argv[2] if len(argv) > 2 else "/modrob0"
    targets = dict((a.split("=")[0], float(a.split("=")[1])) for a in argv[3:]) or DEFAULT_TARGETS
    rospy.init_node("step_response")
    title = rospy.get_param("~title", "%s: simultaneous steps" % ns)
    rows, lock = [], threading.Lock()

    def on_state(msg):
        with lock:
            rows.append((msg.header.stamp.to_sec(), dict(zip(msg.name, msg.position))))
    rospy.Subscriber(ns + "/joint_states", JointState, on_state, queue_size=1000)
    pubs = {j: rospy.Publisher("%s/%s_position_controller/command" % (ns, j), Float64, queue_size=1,
                               latch=True) for j in targets}
    time.sleep(1.0)
    with lock:
        t0 = rows[-1][0]
    for j, v in targets.items():
        pubs[j].publish(Float64(v))
    while not rospy.is_shutdown():
        with lock:
            if rows[-1][0] - t0 > DURATION:
                break
        time.sleep(0.05)
    with lock:
        data = [(t - t0, q) for t, q in rows if t >= t0]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for j, v in targets.items():
        ts = [t for t, _ in data]
        qs = [q[j] for _, q in data]
        q0 = qs[0]
        sign = 1.0 if v >= q0 else -1.0
        overshoot = max(0.0, max(sign * (q - v) for q in qs))
        settle = next((t for t, q in reversed(list(zip(ts, qs))) if abs(q - v) > 0.02), 0.0)
        print("%s: %.2f -> %.2f rad, overshoot %.3f rad, within 0.02 rad after %.2f s, final error %.4f"
              % (j, q0, v, overshoot, settle, qs[-1] - v))
        ax.plot(ts, qs, label="%s -> %.1f" % (j, v))
        ax.axhline(v, ls=":", c="grey", lw=0.8)
    ax.set_xlabel("simulated time [s]")
    ax.set_ylabel("joint angle [rad]")
    ax.set_title(title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print("wrote %s" % out)


if __name__ == "__main__":
    main()

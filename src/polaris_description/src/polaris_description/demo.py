"""`make demo SCENARIO=polaris`: the seed's test and the lap, headless, on the ROS simulator.

Starts polaris.launch (HDL-32E on) on its own master, then (1) the seed's experiment through the
controllers' command topics (2 rad/s, 0.7 rad steering, straighten), (2) back to the spawn point
(reset_world), a street cone on the lap's west side, and the waypoint follower (LapNode: pure
pursuit -> cmd_vel -> Ackermann node) until it stops for the cone seen in /velodyne_points2.
Writes under --out: polaris_seed_speed.png, polaris_seed_path.png, polaris_lap_path.png,
polaris_cloud_top.png, and prints progress and one RESULT line."""
import argparse
import math
import os
import sys
import time

import numpy as np

from polaris_description import parking_lot
from polaris_description import seed_experiment as E
from polaris_description.lap import gap_to
from polaris_description.obstacle import LIDAR_OFFSET
from modrob_sim import scenario_launch

DEMO_CONE = (0.0, 8.0)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", required=True)
    p.add_argument("--timeout", type=float, default=900.0, help="wall-clock limit, s")
    p.add_argument("--scenario", default="polaris", choices=["polaris"], help="(from make demo)")
    a = p.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    log_path = os.path.join(a.out, "polaris_demo_launch.log")
    print("[polaris] starting the simulator (log: %s)" % log_path, flush=True)
    scenario_launch.sigterm_as_exit()
    with open(log_path, "w") as logf:
        launch = scenario_launch.start(["polaris_description", "polaris.launch", "velodyne:=true",
                                        "gui:=false"], logf)
    try:
        return run(a, launch)
    finally:
        scenario_launch.stop(launch)


def run(a, launch):
    import rosgraph
    deadline = time.time() + a.timeout
    while not rosgraph.is_master_online():
        if launch.poll() is not None or time.time() > deadline:
            print("[polaris] the simulator did not start; see the launch log", flush=True)
            return 2
        time.sleep(0.2)
    import rospy
    from gazebo_msgs.srv import SpawnModel
    from geometry_msgs.msg import Pose
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import JointState, PointCloud2
    from std_msgs.msg import Float64
    from std_srvs.srv import Empty

    from polaris_description import geometry as G
    from polaris_description.cloud import xyz_from_cloud
    from polaris_description.figures import path_plot, speed_plot
    from polaris_description.ros_lap import LapNode, default_waypoints
    from polaris_description.transforms import yaw_pitch_roll

    rospy.init_node("polaris_demo", disable_signals=True)
    rospy.wait_for_message("/joint_states", JointState, timeout=300)
    rospy.wait_for_message("/odom", Odometry, timeout=300)
    pubs = {k: rospy.Publisher("/%s/command" % G.CONTROLLERS[k], Float64, queue_size=1)
            for k in ("steer_left", "steer_right", "rear_left", "rear_right")}
    latest = {}

    def on_odom(m):
        q = m.pose.pose.orientation
        latest["s"] = {"t": m.header.stamp.to_sec(), "x": m.pose.pose.position.x, "y": m.pose.pose.position.y,
                       "yaw": yaw_pitch_roll((q.x, q.y, q.z, q.w))[0],
                       "speed": math.hypot(m.twist.twist.linear.x, m.twist.twist.linear.y),
                       "yaw_rate": m.twist.twist.angular.z}
    rospy.Subscriber("/odom", Odometry, on_odom, queue_size=1)

    # ---- 1. the seed's experiment ------------------------------------------------------------
    print("[polaris] 1/2 the seed's test: 2 rad/s on the rear wheels, 0.7 rad steering, straighten",
          flush=True)
    exp = E.SeedExperiment()
    samples = []
    last_print = -10.0
    rate = rospy.Rate(50)
    while not exp.done and time.time() < deadline:
        s = latest.get("s")
        if s is not None and (not samples or s["t"] > samples[-1]["t"]):
            samples.append(s)
            for k, v in exp.step(s).items():
                pubs[k].publish(Float64(v))
            if s["t"] - last_print >= 5.0:
                last_print = s["t"]
                print("[polaris]   t %5.1f s  x %6.2f  y %6.2f  speed %.3f m/s  phase %s"
                      % (s["t"], s["x"], s["y"], s["speed"], exp.phase), flush=True)
        rate.sleep()
    for k in pubs:
        pubs[k].publish(Float64(0.0))
    summary = E.summarize(samples, exp)
    t0 = samples[0]["t"]
    rel = [dict(s, t=s["t"] - t0) for s in samples]
    speed_plot([("polaris (configuration 5)", rel)], os.path.join(a.out, "polaris_seed_speed.png"),
               reference=E.EXPECTED_SPEED, title="Seed test: ground speed (/odom)")
    path_plot([("polaris (configuration 5)", rel)], os.path.join(a.out, "polaris_seed_path.png"),
              title="Seed test: east/north path (/odom)")
    print("[polaris]   speed %.3f m/s (%+.1f %% of 0.64), heading change %.0f deg"
          % (summary["mean_speed"], 100 * summary["speed_error"], summary["heading_change_deg"]), flush=True)

    # ---- 2. the lap with a cone on it ------------------------------------------------------
    print("[polaris] 2/2 the lap: back to the start, a cone at (%.1f, %.1f) on the lap" % DEMO_CONE,
          flush=True)
    rospy.ServiceProxy("/gazebo/reset_world", Empty)()
    t_reset = rospy.get_time()        # /odom from before the reset (the seed test's end) is not the lap's
    spawn = rospy.ServiceProxy("/gazebo/spawn_sdf_model", SpawnModel)
    r = spawn(model_name="cone_on_path", model_xml="<sdf version='1.6'>%s</sdf>"
              % parking_lot.cone_model_sdf("cone_on_path", 0.0, 0.0),
              robot_namespace="", initial_pose=Pose(), reference_frame="world")
    if not r.success:
        print("[polaris] could not spawn the cone: %s" % r.status_message, flush=True)
    else:
        from gazebo_msgs.srv import SetModelState
        from gazebo_msgs.msg import ModelState
        ms = ModelState(model_name="cone_on_path", reference_frame="world")
        ms.pose.position.x, ms.pose.position.y = DEMO_CONE
        ms.pose.orientation.w = 1.0
        rospy.ServiceProxy("/gazebo/set_model_state", SetModelState)(ms)
    clouds = []

    def on_cloud(m):
        s = latest.get("s")
        if s is not None and len(clouds) < 400:
            clouds.append((s["x"], s["y"], s["yaw"], xyz_from_cloud(m)))
    rospy.Subscriber("/velodyne_points2", PointCloud2, on_cloud, queue_size=1, buff_size=2 ** 22)
    lap = LapNode(default_waypoints())
    lap_samples = []
    last_print = -10.0
    min_gap = math.inf
    t_start = None
    while time.time() < deadline:
        s = latest.get("s")
        if s is not None and s["t"] > t_reset:
            t_start = s["t"] if t_start is None else t_start
            if not lap_samples or s["t"] > lap_samples[-1]["t"]:
                lap_samples.append(s)
                min_gap = min(min_gap, gap_to(DEMO_CONE, s["x"], s["y"], s["yaw"]))
            if s["t"] - last_print >= 5.0:
                last_print = s["t"]
                print("[polaris]   t %5.1f s  x %6.2f  y %6.2f  speed %.2f m/s  %s"
                      % (s["t"], s["x"], s["y"], s["speed"], lap.state), flush=True)
            if (lap.guard.stopped and s["speed"] < 0.02) or lap.pp.done or s["t"] - t_start > 150.0:
                break
        time.sleep(0.05)
    lap.timer.shutdown()
    wps = default_waypoints()

    def extra(ax):
        ax.plot([w[0] for w in wps], [w[1] for w in wps], "k.", ms=3, label="waypoints")
        ax.plot([DEMO_CONE[0]], [DEMO_CONE[1]], "^", color="orange", ms=10, label="cone")
    path_plot([("driven (/odom)", lap_samples)], os.path.join(a.out, "polaris_lap_path.png"),
              title="Lap: pure pursuit + Ackermann, stop for the cone", extra=extra)
    cloud_top_view(clouds, os.path.join(a.out, "polaris_cloud_top.png"))
    stopped = lap.guard.stopped
    ok = abs(summary["speed_error"]) <= 0.03 and 75 <= summary["heading_change_deg"] <= 105 and stopped \
        and min_gap > 0.0 and lap.max_cross_track < 1.0
    print("RESULT: %s seed test %.3f m/s (%+.1f %%), turned %.0f deg; lap %s, clearance to the cone %.2f m, "
          "max path error %.2f m; figures in %s"
          % ("PASS" if ok else "FAIL", summary["mean_speed"], 100 * summary["speed_error"],
             summary["heading_change_deg"], "stopped for the cone" if stopped else lap.state, min_gap,
             lap.max_cross_track, a.out), flush=True)
    rospy.signal_shutdown("demo done")
    return 0 if ok else 1


def cloud_top_view(clouds, path):
    """The accumulated clouds in the world frame, seen from above, with the cones' true positions."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    pts = []
    for (x, y, yaw, p) in clouds[::2]:
        if len(p) == 0:
            continue
        c, s = math.cos(yaw), math.sin(yaw)
        lx, ly = p[:, 0] + LIDAR_OFFSET[0], p[:, 1] + LIDAR_OFFSET[1]
        w = np.stack([x + c * lx - s * ly, y + s * lx + c * ly, p[:, 2] + LIDAR_OFFSET[2] + 0.32], axis=1)
        pts.append(w)
    fig, ax = plt.subplots(figsize=(9, 7))
    if pts:
        w = np.concatenate(pts)
        w = w[w[:, 2] > 0.05] if np.any(w[:, 2] > 0.05) else w
        sc = ax.scatter(w[:, 0], w[:, 1], c=w[:, 2], s=1, cmap="viridis")
        fig.colorbar(sc, ax=ax, label="height [m]")
    ax.plot([c.x for c in parking_lot.CONES] + [DEMO_CONE[0]],
            [c.y for c in parking_lot.CONES] + [DEMO_CONE[1]],
            "r+", ms=12, label="cones (true)")
    ax.set_aspect("equal")
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_title("HDL-32E points above the ground (world frame, %d scans)" % len(pts))
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())

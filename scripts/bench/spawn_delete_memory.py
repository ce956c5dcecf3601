#!/usr/bin/env python3
"""Memory of the /gazebo node over spawn/delete cycles (a benchmark, not a test).

Each cycle spawns (under a new name) a 3-joint arm with a ros_control plugin and an IMU sensor plugin
(src/modrob_sim/test/fixtures/control/arm_3dof.urdf + an <gazebo reference><sensor>), loads and
starts joint_state_controller and a JointTrajectoryController (an action server) through the
controller manager's services, stops and unloads them and deletes the model: everything a
spawn/delete leaves behind on the ROS side (publishers, subscribers, services, action servers,
plugin objects, caches) shows up as resident memory that keeps growing.

    bash scripts/bench/spawn_delete_memory.sh                     # 1500 cycles, writes docs
    spawn_delete_memory.py --cycles 300 --every 25 --no-write     # quick look
    spawn_delete_memory.py --memdebug 8 --cycles 200 --every 50   # + the node's tracemalloc diffs

The node runs headless at real_time_factor 1 (physics steps and plugins run between the
cycles, as in use). RSS (VmRSS of the node's process) is read every ``--every`` cycles. Writes
the "Simulator node memory" section of docs/benchmarks.md and
docs/images/benchmarks/spawn_delete_memory.png unless --no-write. ``--root`` runs the node of
another checkout (for a before/after comparison in one plot: ``--compare ROOT``).
"""
import argparse
import os
import re
import signal
import subprocess
import sys
import time

from procs import free_port, scratch_dir, stop, terminate

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SECTION = "Simulator node memory"
PNG = "docs/images/benchmarks/spawn_delete_memory.png"
NS = "/arm3"

IMU = """
  <gazebo reference="link2">
    <sensor name="imu_sensor" type="imu"><always_on>true</always_on><update_rate>100</update_rate>
      <plugin filename="libgazebo_ros_imu_sensor.so" name="imu_plugin">
        <topicName>imu</topicName><bodyName>link2</bodyName><updateRateHZ>100.0</updateRateHZ>
        <gaussianNoise>0.0</gaussianNoise><frameName>link2</frameName>
      </plugin><pose>0 0 0 0 0 0</pose></sensor>
  </gazebo>
</robot>"""


def rss_kib(pid):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def robot_xml(root):
    with open(os.path.join(root, "src/modrob_sim/test/fixtures/control/arm_3dof.urdf")) as f:
        xml = f.read()
    links = re.findall(r'<link name="([^"]+)"', xml)
    return xml.replace("</robot>", IMU.replace("link2", links[-1]))


def start_master():
    """A roscore on a free port for the whole benchmark (this process's rospy stays bound to the
    master it first talked to, so every node run uses the same one)."""
    env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:%d" % free_port(),
               ROS_HOME=scratch_dir("spawn_delete_memory_roshome_"))
    core = subprocess.Popen(["roscore", "-p", env["ROS_MASTER_URI"].rsplit(":", 1)[1]], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    deadline = time.time() + 60
    while subprocess.run(["rosnode", "list"], env=env, capture_output=True).returncode != 0:
        if time.time() > deadline:
            raise RuntimeError("roscore did not come up")
        time.sleep(0.2)
    return core, env


def run(root, cycles, every, memdebug, log, env):
    """One node of checkout ``root``; returns [(cycle, rss_kib)] and the debug reports."""
    import rospy
    import rosparam
    from controller_manager_msgs.srv import LoadController, SwitchController, UnloadController
    from gazebo_msgs.srv import DeleteModel, SpawnModel
    from geometry_msgs.msg import Pose
    from std_srvs.srv import Trigger

    node_env = dict(env)
    if memdebug:
        node_env["MODROB_SIM_MEMDEBUG"] = memdebug
    if os.path.realpath(root) != ROOT:  # the other checkout's Python packages and messages
        for var in ("PYTHONPATH", "ROS_PACKAGE_PATH", "CMAKE_PREFIX_PATH", "LD_LIBRARY_PATH"):
            if var in node_env:
                node_env[var] = node_env[var].replace(ROOT, os.path.realpath(root))
    node = None
    try:
        node = subprocess.Popen([sys.executable, os.path.join(root, "src/modrob_sim/scripts/gazebo"),
                                 "_real_time_factor:=1", "__name:=gazebo"], env=node_env, stdout=log,
                                stderr=subprocess.STDOUT)
        if not rospy.core.is_initialized():
            rospy.init_node("spawn_delete_memory", anonymous=True, disable_signals=True)
        for name, value in rosparam.load_file(os.path.join(
                root, "src/modrob_sim/test/fixtures/control/arm3_controllers.yaml"))[0][0].items():
            rospy.set_param(NS + "/" + name, value)
        rospy.wait_for_service("/gazebo/spawn_urdf_model", 60)
        spawn = rospy.ServiceProxy("/gazebo/spawn_urdf_model", SpawnModel, persistent=True)
        delete = rospy.ServiceProxy("/gazebo/delete_model", DeleteModel, persistent=True)
        mem = rospy.ServiceProxy("/gazebo/debug/memory", Trigger) if memdebug else None
        xml = robot_xml(root)
        samples, reports = [], []
        for i in range(cycles + 1):
            if i % every == 0:
                samples.append((i, rss_kib(node.pid)))
                if mem is not None and i > 0:
                    reports.append((i, mem().message))
                print("cycle %d rss %d KiB" % samples[-1], flush=True)
            if i == cycles:
                break
            name = "arm3_%d" % i   # a new name each time, as a fuzz or a spawner of parts does
            r = spawn(model_name=name, model_xml=xml, robot_namespace=NS, initial_pose=Pose(),
                      reference_frame="world")
            assert r.success, r.status_message
            cm = NS + "/controller_manager/"
            rospy.wait_for_service(cm + "switch_controller", 30)
            for c in ("joint_state_controller", "arm_controller"):
                assert rospy.ServiceProxy(cm + "load_controller", LoadController)(name=c).ok, c
            sw = rospy.ServiceProxy(cm + "switch_controller", SwitchController)
            assert sw(start_controllers=["joint_state_controller", "arm_controller"], stop_controllers=[],
                      strictness=2).ok
            assert sw(start_controllers=[], stop_controllers=["joint_state_controller", "arm_controller"],
                      strictness=2).ok
            for c in ("joint_state_controller", "arm_controller"):
                assert rospy.ServiceProxy(cm + "unload_controller", UnloadController)(name=c).ok, c
            r = delete(model_name=name)
            assert r.success, r.status_message
        return samples, reports
    finally:
        terminate(node, 30.0, signal.SIGINT)


def growth(samples, skip):
    """KiB per cycle fitted over the samples from cycle ``skip`` on (least squares)."""
    pts = [(c, r) for c, r in samples if c >= skip]
    n = len(pts)
    if n < 2:
        return float("nan")
    mx = sum(c for c, _ in pts) / n
    my = sum(r for _, r in pts) / n
    sxx = sum((c - mx) ** 2 for c, _ in pts)
    return sum((c - mx) * (r - my) for c, r in pts) / sxx


def plot(curves, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 3.6), dpi=100)
    for label, samples in curves:
        ax.plot([c for c, _ in samples], [r / 1024.0 for _, r in samples], marker=".", label=label)
    ax.set_xlabel("spawn/delete cycles (3-joint arm + ros_control + IMU, 2 controllers each)")
    ax.set_ylabel("/gazebo RSS (MiB)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)


def write_section(text):
    path = os.path.join(ROOT, "docs", "benchmarks.md")
    with open(path) as f:
        doc = f.read()
    head = "## %s\n" % SECTION
    if head in doc:
        start = doc.index(head)
        nxt = doc.find("\n## ", start + len(head))
        doc = doc[:start] + text + (doc[nxt + 1:] if nxt >= 0 else "")
    else:
        doc = doc.rstrip("\n") + "\n\n" + text
    with open(path, "w") as f:
        f.write(doc)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cycles", type=int, default=1500)
    ap.add_argument("--every", type=int, default=50)
    ap.add_argument("--root", default=ROOT, help="checkout whose node runs (default: this one)")
    ap.add_argument("--compare", help="also run the node of this checkout (e.g. before a fix)")
    ap.add_argument("--compare-label", default="before")
    ap.add_argument("--compare-log", help="instead of running --compare: the 'cycle N rss X KiB' lines "
                                          "a previous run of this script printed for it")
    ap.add_argument("--this-log", help="no run at all: this tree's samples from a previous run's output")
    ap.add_argument("--memdebug", nargs="?", const="gc", default="",
                    help="MODROB_SIM_MEMDEBUG for the node (gc: object counts and malloc statistics; "
                         "N: + tracemalloc with N frames) and print its reports")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    log_path = os.path.join(ROOT, "out", "bench", "spawn_delete_memory_node.log")     # the node's output
    os.makedirs(os.path.dirname(log_path), exist_ok=True)
    log = open(log_path, "w")
    curves = []
    if args.compare_log:
        with open(args.compare_log) as f:
            found = re.findall(r"^cycle (\d+) rss (\d+) KiB$", f.read(), re.M)
        curves.append((args.compare_label, [(int(c), int(r)) for c, r in found], float("nan")))
    if args.this_log:
        with open(args.this_log) as f:
            found = re.findall(r"^cycle (\d+) rss (\d+) KiB$", f.read(), re.M)
        curves.append(("this tree", [(int(c), int(r)) for c, r in found], float("nan")))
        args.cycles = curves[-1][1][-1][0]
    core, env = start_master() if not args.this_log else (None, None)
    try:
        runs = ([(args.compare_label, args.compare)] if args.compare else []) + [("this tree", args.root)]
        for label, root in (runs if not args.this_log else []):
            t0 = time.time()
            samples, reports = run(root, args.cycles, args.every, args.memdebug, log, env)
            for cycle, text in reports:
                print("---- node's memory report at cycle %d\n%s" % (cycle, text))
            curves.append((label, samples, time.time() - t0))
    finally:
        stop(core, 30.0)
    skip = min(args.cycles // 3, 500)
    rows = []
    for label, samples, secs in curves:
        at_skip = [r for c, r in samples if c >= skip][0]
        rows.append("| %s | %d | %.1f | %.1f | %.1f | %.2f | %.0f |" % (
            label, samples[-1][0], samples[0][1] / 1024.0, at_skip / 1024.0, samples[-1][1] / 1024.0,
            growth(samples, skip), secs))
        print(rows[-1])
    if args.no_write:
        return 0
    plot([(lbl + " (%+.2f KiB/cycle after %d)" % (growth(s, skip), skip), s) for lbl, s, _ in curves],
         os.path.join(ROOT, PNG))
    text = ("## %s\n\n`bash scripts/bench/spawn_delete_memory.sh` (%s): resident memory of the `/gazebo`\n"
            "node over spawn/delete cycles (a new model name each cycle) of a 3-joint arm with a\n"
            "ros_control plugin and an IMU sensor; each cycle also loads, starts, stops and unloads\n"
            "joint_state_controller and a JointTrajectoryController. Growth is the least-squares slope\n"
            "from cycle %d on.\n\n"
            "| node | cycles | RSS at start (MiB) | RSS at cycle %d (MiB) | RSS at the end (MiB) | "
            "growth from cycle %d (KiB/cycle) | wall (s) |\n"
            "|---|---|---|---|---|---|---|\n%s\n\n![RSS over spawn/delete cycles](%s)\n"
            % (SECTION, time.strftime("%Y-%m-%d"), skip, skip, skip, "\n".join(rows),
               os.path.relpath(os.path.join(ROOT, PNG), os.path.join(ROOT, "docs"))))
    write_section(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())

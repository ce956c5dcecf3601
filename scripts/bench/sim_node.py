#!/usr/bin/env python3
"""Simulator node benchmark (not a test): steps per second and real-time factor of the whole
/gazebo node (physics + plugin + /clock + model/link states + ROS services), headless,
real_time_factor 0, 1 ms steps, on the physics-core benchmark's scene (scripts/bench/physics_core.py:
a 6-joint arm of 1.5 kg links on a table held by a PD loop, 5 loose cylinders), compared with
PyBullet stepping the same URDF files in the same run.

    bash scripts/bench/sim_node.sh                      # uses scripts/bench/.venv-bench (PyBullet)
    sim_node.py --seconds 10 --repeat 2 [--no-write] [--no-pybullet]

The PD loop runs inside the node as a plugin (this module registers it when the node imports it
through ~plugin_modules), exactly where ros_control's update runs. A subscriber in this process
takes /clock, /gazebo/model_states and /gazebo/link_states, so that the publishing is real.
Writes the "Simulator node" section of docs/benchmarks.md (only that section) unless --no-write.
"""
import argparse
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import physics_core as scene  # noqa: E402  (the same scene and PD gains)
from procs import cpu_seconds, free_port, terminate  # noqa: E402

SECTION = "Simulator node"
PLUGIN = "libmodrob_bench_pd.so"


# ---- the PD loop as a plugin of the node (imported by the node through ~plugin_modules) -------
class PdPlugin(object):
    def __init__(self, model):
        self.pairs = [(model.joints["joint%d" % (i + 1)], q) for i, q in enumerate(scene.Q_HOLD)]

    def update(self, _t, _dt):
        for j, q in self.pairs:
            j.set_effort(scene.KP * (q - j.position) - scene.KD * j.velocity)


def _register():
    try:
        from modrob_sim.gazebo_ros.plugins import register_plugin
    except ImportError:
        return
    register_plugin(PLUGIN, lambda model, spec, ctx: PdPlugin(model))


_register()


# ---- the benchmark ---------------------------------------------------------------------------
def arm_with_plugin():
    return scene.arm_urdf().replace("</robot>", '<gazebo><plugin name="pd" filename="%s"/></gazebo></robot>'
                                    % PLUGIN)


def run_node(seconds, clock_hz, subscribe, env):
    """Start /gazebo, build the scene through the services, run ``seconds`` wall seconds."""
    import rospy
    from gazebo_msgs.msg import LinkStates, ModelStates
    from gazebo_msgs.srv import GetWorldProperties, SetModelConfiguration, SpawnModel
    from geometry_msgs.msg import Point, Pose, Quaternion
    from rosgraph_msgs.msg import Clock
    from std_srvs.srv import Empty

    node = subprocess.Popen([sys.executable, os.path.join(ROOT, "src/modrob_sim/scripts/gazebo"),
                             "_real_time_factor:=0", "_paused:=true", "_pub_clock_frequency:=%g" % clock_hz,
                             "_plugin_modules:=[sim_node]", "_rtf_log_period:=0"],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        ns = "/gazebo/"
        rospy.wait_for_service(ns + "step", timeout=60)
        spawn = rospy.ServiceProxy(ns + "spawn_urdf_model", SpawnModel)
        world = rospy.ServiceProxy(ns + "get_world_properties", GetWorldProperties)
        ok = [spawn("table", scene.table_urdf(), "", Pose(orientation=Quaternion(0, 0, 0, 1)), "").success,
              spawn("arm", arm_with_plugin(), "", Pose(orientation=Quaternion(0, 0, 0, 1)), "").success,
              rospy.ServiceProxy(ns + "set_model_configuration", SetModelConfiguration)(
                  "arm", "", ["joint%d" % (i + 1) for i in range(scene.N_JOINTS)], scene.Q_HOLD).success]
        for k, (x, y) in enumerate(scene.OBJECTS):
            pose = Pose(Point(x, y, scene.TABLE_TOP + scene.OBJ_H / 2 - 0.001), Quaternion(0, 0, 0, 1))
            ok.append(spawn("can%d" % k, scene.object_urdf(), "", pose, "").success)
        if not all(ok):
            raise RuntimeError("building the scene failed: %s" % ok)
        counts = {"clock": 0, "model_states": 0, "link_states": 0}
        subs = []
        if subscribe:
            def counter(key):
                def cb(_msg):
                    counts[key] += 1
                return cb
            subs = [rospy.Subscriber("/clock", Clock, counter("clock"), queue_size=10),
                    rospy.Subscriber(ns + "model_states", ModelStates, counter("model_states"), queue_size=1),
                    rospy.Subscriber(ns + "link_states", LinkStates, counter("link_states"), queue_size=1)]
            time.sleep(1.0)                     # let the connections come up
        rospy.ServiceProxy(ns + "unpause_physics", Empty)()
        time.sleep(0.5)                         # settle (the PD pulls the arm in)
        t0, w0, c0 = world().sim_time, time.perf_counter(), cpu_seconds(node.pid)
        n0 = dict(counts)
        time.sleep(seconds)
        t1, w1, c1 = world().sim_time, time.perf_counter(), cpu_seconds(node.pid)
        rospy.ServiceProxy(ns + "pause_physics", Empty)()
        for s in subs:
            s.unregister()
        steps = (t1 - t0) / 0.001
        wall = w1 - w0
        return {"steps_per_s": steps / wall, "cpu_steps_per_s": steps / max(1e-9, c1 - c0),
                "rtf": (t1 - t0) / wall, "cpu_load": (c1 - c0) / wall,
                "rates": {k: (counts[k] - n0[k]) / wall for k in counts}}
    finally:
        terminate(node)


def write_section(text):
    path = os.path.join(ROOT, "docs", "benchmarks.md")
    old = open(path).read() if os.path.exists(path) else "# Benchmarks\n"
    pattern = re.compile(r"^## %s\n.*?(?=^## |\Z)" % re.escape(SECTION), re.S | re.M)
    block = "## %s\n\n%s\n" % (SECTION, text.strip() + "\n")
    new = pattern.sub(lambda _m: block, old) if pattern.search(old) else old.rstrip("\n") + "\n\n" + block
    with open(path, "w") as f:
        f.write(new)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=10.0, help="wall seconds timed per run")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--no-pybullet", action="store_true")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()

    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % port,
               PYTHONPATH=HERE + os.pathsep + os.environ.get("PYTHONPATH", ""))
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    core = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    files = scene.scene_files("modrob_bench_node_")
    try:
        import rosgraph
        deadline = time.time() + 30
        while not rosgraph.is_master_online() and time.time() < deadline:
            time.sleep(0.2)
        import rospy
        rospy.set_param("/use_sim_time", True)
        rospy.init_node("sim_node_bench", disable_signals=True)
        variants = [("node, /clock at 1 kHz wall (default), states 100 Hz, subscribed", 1000.0, True),
                    ("node, /clock every step, states 100 Hz, subscribed", 0.0, True),
                    ("node, no subscribers", 1000.0, False)]
        runs = {name: [] for name, _, _ in variants}
        bullet = []
        for r in range(args.repeat):
            for name, clock_hz, sub in variants:
                res = run_node(args.seconds, clock_hz, sub, env)
                runs[name].append(res)
                print("[bench] run %d %-62s %7.0f steps/s wall (RTF %.1f), %7.0f per CPU s, load %.2f, "
                      "clock %.0f/s, model_states %.0f/s"
                      % (r + 1, name, res["steps_per_s"], res["rtf"], res["cpu_steps_per_s"],
                         res["cpu_load"], res["rates"]["clock"], res["rates"]["model_states"]), flush=True)
            if not args.no_pybullet:
                try:
                    b = scene.run_pybullet(int(args.seconds * 2000), files)
                    bullet.append(b)
                    print("[bench] run %d PyBullet %7.0f steps/s wall, %7.0f per CPU s"
                          % (r + 1, b["wall_steps_per_s"], b["steps_per_s"]), flush=True)
                except ImportError:
                    print("[bench] pybullet not importable: run through sim_node.sh", file=sys.stderr)
    finally:
        terminate(core)

    ref = max(bullet, key=lambda b: b["steps_per_s"]) if bullet else None
    lines = ["| configuration | steps/s per CPU s (best of %d) | vs PyBullet (CPU) | steps/s wall | "
             "real-time factor (wall) | CPU load (cores) | /clock msgs/s received | model_states/s |"
             % args.repeat, "|---|---|---|---|---|---|---|---|"]
    for name, rs in runs.items():
        b = max(rs, key=lambda x: x["cpu_steps_per_s"])
        ratio = "%.2fx" % (b["cpu_steps_per_s"] / ref["steps_per_s"]) if ref else "n/a"
        lines.append("| %s | %.0f | %s | %.0f | %.1f | %.2f | %.0f | %.0f |" % (
            name, b["cpu_steps_per_s"], ratio, b["steps_per_s"], b["rtf"], b["cpu_load"],
            b["rates"]["clock"], b["rates"]["model_states"]))
    if ref:
        w = ref["wall_steps_per_s"]
        lines.append("| PyBullet 3.2.7, same scene, same run (no ROS) | %.0f | 1.00x | %.0f | %.1f | - | - | "
                     "- |" % (ref["steps_per_s"], w, w / 1000.0))
    table = "\n".join(lines)
    print(table)
    try:
        rev = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                             text=True).stdout.strip()
    except OSError:
        rev = "?"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = [ln.split(":", 1)[1].strip() for ln in f if ln.startswith("model name")][0]
    except (OSError, IndexError):
        cpu = "?"
    text = """Command: `bash scripts/bench/sim_node.sh` (%g wall seconds timed per run after 0.5 s settling,
best of %d interleaved runs). Measured %s on %s (%d cores), commit %s.

The whole `/gazebo` node as a user runs it (`real_time_factor` 0, 1 ms steps, headless), on the
physics-core scene (6-joint arm of 1.5 kg links on a table, held by a PD loop that runs as a node
plugin where ros_control's update runs; 5 loose cylinders). The scene is built through the
services (`spawn_urdf_model`, `set_model_configuration`). A subscriber in the benchmark process
takes `/clock`, `/gazebo/model_states` and `/gazebo/link_states` (the node skips serialising
topics nobody subscribes to). PyBullet steps the same
URDF files with the same PD loop in the benchmark process, in the same run, without ROS.
The machine is shared (other builds and tests run at the same time), so the comparison divides by
CPU time, as the physics-core benchmark does: "steps/s per CPU s" is steps per second of the node
process's CPU time (all its threads: physics, plugin, publishing, rospy's transport threads);
PyBullet's is per second of the benchmark process's CPU time. Wall-clock figures are beside them.

%s

Target: the node >= 0.5x PyBullet's steps/s. Where the time goes: the physics step itself (see
"Physics core"), then per-step Python in the node (the plugin call, the clock throttle check,
setting rospy's time), and the publishing: one `/clock` message to one subscriber costs the node
about 100 us of CPU (serialising plus rospy's transport thread; compare the first two rows), more
than the physics step, so `/clock` on every step halves the speed; the default 1 kHz wall-clock
throttle (`~pub_clock_frequency`, Gazebo's parameter) bounds that cost at any speed. Model and
link states go out at 100 Hz of simulated time (`~publish_rate`), i.e. ~%s/s at this speed.
""" % (args.seconds, args.repeat, time.strftime("%Y-%m-%d"), cpu, os.cpu_count(), rev,
       table + "\n\nLoad average during the run: %s." % " / ".join("%.1f" % v for v in os.getloadavg()),
       "%.0f" % (max(runs[variants[0][0]], key=lambda x: x["steps_per_s"])["rtf"] * 100))
    if ref:
        verdicts = []
        for name, rs in runs.items():
            ratio = max(x["cpu_steps_per_s"] for x in rs) / ref["steps_per_s"]
            verdicts.append("%s: %.2fx (%s)" % (name, ratio, "meets" if ratio >= 0.5 else "MISSES"))
        text += "\nAgainst the 0.5x target: " + "; ".join(verdicts) + ".\n"
    if not args.no_write:
        print("[bench] wrote %s" % write_section(text))


if __name__ == "__main__":
    main()

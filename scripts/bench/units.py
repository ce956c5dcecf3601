#!/usr/bin/env python3
"""The benchmark units that scripts/bench/run.py runs, each in its own process (one rospy node per
process, its own ROS master on a free port), so that units can run side by side (run.py -j N).

    python3 units.py UNIT [--seconds S] [--rep K]      prints one JSON object on its last line

A unit measures our figure AND its peer in the same process and run, so that a busy machine hits
both alike; run.py takes the median, min and max over repetitions and the ratio per repetition.
Units: physics_core, node, sensor_arm, mobile, bulbs_one, bulbs_two, startup, rss, kdl_fk,
polaris_pace, katana_pace, ptrz_pace.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import physics_core as scene  # noqa: E402  (the scene, the PD gains, our engine and PyBullet's runs)
from procs import (cpu_seconds, descendants, free_port, scratch_dir, stop, terminate,  # noqa: E402
                   thread_cpu_seconds)

N = scene.N_JOINTS
JOINTS = ["joint%d" % (i + 1) for i in range(N)]


# ---- helpers ------------------------------------------------------------------------------------
def find_node(root_pid, needle="modrob_sim/gazebo"):
    for pid in descendants(root_pid):
        try:
            with open("/proc/%d/cmdline" % pid, "rb") as f:
                if needle.encode() in f.read():
                    return pid
        except OSError:
            pass
    return None


def rss_mb(pid):
    with open("/proc/%d/status" % pid) as f:
        for ln in f:
            if ln.startswith("VmRSS:"):
                return int(ln.split()[1]) / 1024.0
    return float("nan")


class Master(object):
    """roscore on a free port; ROS_MASTER_URI of this process points at it."""

    def __init__(self):
        self.port = free_port()
        os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % self.port
        self.proc = subprocess.Popen(["roscore", "-p", str(self.port)], stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL, start_new_session=True)
        import rosgraph
        deadline = time.time() + 60
        while not rosgraph.is_master_online():
            if time.time() > deadline:
                raise RuntimeError("roscore did not come up on port %d" % self.port)
            time.sleep(0.1)

    def close(self):
        stop(self.proc, 15.0)


# ---- MuJoCo: the same URDF files, the same PD law ----------------------------------------------------
def run_mujoco(steps, settle=500):
    """MuJoCo loads the same three URDF strings (MjSpec.from_string), attached into one world;
    the cans get free joints (MuJoCo's URDF import leaves a root link static). The PD law is the
    same (tau = KP (q* - q) - KD dq), written as a MuJoCo affine actuator per joint so that the
    damping term is integrated implicitly (implicitfast): as an explicit applied force, KD = 8 on
    the last link (about its axis 1.2e-3 kg m^2) at 1 ms steps diverges in MuJoCo."""
    import mujoco
    import numpy as np
    w = mujoco.MjSpec()
    w.option.timestep = 0.001
    w.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST

    def attach(urdf, prefix, pos=(0.0, 0.0, 0.0)):
        w.attach(mujoco.MjSpec.from_string(urdf), frame=w.worldbody.add_frame(pos=list(pos)), prefix=prefix)
    attach(scene.table_urdf(), "table_")
    attach(scene.arm_urdf(), "arm_")
    for k, (x, y) in enumerate(scene.OBJECTS):
        attach(scene.object_urdf(), "can%d_" % k, (x, y, scene.TABLE_TOP + scene.OBJ_H / 2 - 0.001))
        w.body("can%d_can" % k).add_freejoint()
    for j in JOINTS:
        w.add_actuator(name=j + "_pd", target="arm_" + j, trntype=mujoco.mjtTrn.mjTRN_JOINT,
                       gaintype=mujoco.mjtGain.mjGAIN_FIXED, biastype=mujoco.mjtBias.mjBIAS_AFFINE,
                       gainprm=[scene.KP] + [0.0] * 9, biasprm=[0.0, -scene.KP, -scene.KD] + [0.0] * 7)
    m = w.compile()
    m.opt.iterations = 50
    d = mujoco.MjData(m)
    qa = np.array([m.jnt_qposadr[m.joint("arm_" + j).id] for j in JOINTS])
    qh = np.array(scene.Q_HOLD)
    d.qpos[qa] = qh
    mujoco.mj_forward(m, d)
    cans = [m.body("can%d_can" % k).id for k in range(len(scene.OBJECTS))]

    def step(n):
        for _ in range(n):
            d.ctrl[:] = qh
            mujoco.mj_step(m, d)
    step(settle)
    start = d.xpos[cans].copy()
    t0, c0 = time.perf_counter(), time.process_time()
    step(steps)
    dt, cpu = time.perf_counter() - t0, time.process_time() - c0
    return {"steps_per_s": steps / cpu, "wall_steps_per_s": steps / dt, "contacts": int(d.ncon),
            "can_drift_m": float(np.linalg.norm(d.xpos[cans] - start, axis=1).max()),
            "arm_err_rad": float(np.abs(d.qpos[qa] - qh).max()), "version": mujoco.__version__}


def unit_physics_core(args):
    files = scene.scene_files()
    steps = int(args.seconds * 1000) if args.seconds else 20000
    out = {"sleeping": scene.run_ours(steps, None),
           "awake": scene.run_ours(steps, None, auto_disable=False),
           "pybullet": scene.run_pybullet(steps, files),
           # the same with PyBullet's early exit off: all 50 solver iterations, as ODE's quickStep
           "pybullet_all_iters": scene.run_pybullet(steps, files, residual_threshold=0.0)}
    try:
        out["mujoco"] = run_mujoco(steps)
    except ImportError as exc:
        out["mujoco_missing"] = str(exc)
    return out


# ---- the full node with ros_control -------------------------------------------------------------------
def arm_with_ros_control(ns="/arm"):
    trans = "".join(
        '<transmission name="t%d"><type>transmission_interface/SimpleTransmission</type>'
        '<joint name="%s"><hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface>'
        '</joint><actuator name="m%d"><mechanicalReduction>1</mechanicalReduction></actuator></transmission>'
        % (i, j, i) for i, j in enumerate(JOINTS))
    plugin = ('<gazebo><plugin name="gazebo_ros_control" filename="libgazebo_ros_control.so">'
              '<robotNamespace>%s</robotNamespace></plugin></gazebo>' % ns)
    return scene.arm_urdf().replace("</robot>", trans + plugin + "</robot>")


CONTROLLERS = ["joint_state_controller"] + ["%s_position_controller" % j for j in JOINTS]


def controller_params(ns="/arm"):
    p = {"joint_state_controller": {"type": "joint_state_controller/JointStateController",
                                    "publish_rate": 50}}
    for j, q in zip(JOINTS, scene.Q_HOLD):
        p["%s_position_controller" % j] = {"type": "effort_controllers/JointPositionController", "joint": j,
                                           "pid": {"p": scene.KP, "i": 0.0, "d": scene.KD}}
    return {ns: p}


def start_node(extra=(), env=None):
    return subprocess.Popen([sys.executable, os.path.join(ROOT, "src/modrob_sim/scripts/gazebo"),
                             "_real_time_factor:=0", "_paused:=true", "_rtf_log_period:=0"] + list(extra),
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def build_scene(ns="/arm"):
    """The physics-core scene through the services, the arm with its 7 controllers running."""
    import rospy
    from controller_manager_msgs.srv import LoadController, SwitchController
    from gazebo_msgs.srv import SetModelConfiguration, SpawnModel
    from geometry_msgs.msg import Point, Pose, Quaternion
    from std_msgs.msg import Float64
    g = "/gazebo/"
    rospy.wait_for_service(g + "spawn_urdf_model", timeout=60)
    for k, v in controller_params(ns)[ns].items():
        rospy.set_param("%s/%s" % (ns, k), v)
    spawn = rospy.ServiceProxy(g + "spawn_urdf_model", SpawnModel)
    ident = Quaternion(0, 0, 0, 1)
    ok = [spawn("table", scene.table_urdf(), "", Pose(orientation=ident), "").success,
          spawn("arm", arm_with_ros_control(ns), "", Pose(orientation=ident), "").success,
          rospy.ServiceProxy(g + "set_model_configuration", SetModelConfiguration)(
              "arm", "", JOINTS, scene.Q_HOLD).success]
    for k, (x, y) in enumerate(scene.OBJECTS):
        pose = Pose(Point(x, y, scene.TABLE_TOP + scene.OBJ_H / 2 - 0.001), ident)
        ok.append(spawn("can%d" % k, scene.object_urdf(), "", pose, "").success)
    rospy.wait_for_service(ns + "/controller_manager/load_controller", timeout=30)
    load = rospy.ServiceProxy(ns + "/controller_manager/load_controller", LoadController)
    ok += [load(c).ok for c in CONTROLLERS]
    ok.append(rospy.ServiceProxy(ns + "/controller_manager/switch_controller", SwitchController)(
        CONTROLLERS, [], 2, False, 0.0).ok)
    if not all(ok):
        raise RuntimeError("building the scene failed: %s" % ok)
    pubs = []
    for j, q in zip(JOINTS, scene.Q_HOLD):
        pub = rospy.Publisher("%s/%s_position_controller/command" % (ns, j), Float64, queue_size=1,
                              latch=True)
        pub.publish(Float64(q))
        pubs.append(pub)
    return pubs


def run_node_once(seconds, clock_hz, ns="/arm", env=None, roscpp=True):
    import rospy
    from gazebo_msgs.msg import LinkStates, ModelStates
    from gazebo_msgs.srv import GetWorldProperties
    from rosgraph_msgs.msg import Clock
    from sensor_msgs.msg import JointState
    from std_srvs.srv import Empty
    node = start_node(["_pub_clock_frequency:=%g" % clock_hz, "_native_publishing:=%s" % str(roscpp).lower()],
                      env=env)
    try:
        pubs = build_scene(ns)
        g = "/gazebo/"
        counts = {"clock": 0, "model_states": 0, "link_states": 0, "joint_states": 0}

        def counter(key):
            def cb(_msg):
                counts[key] += 1
            return cb
        subs = [rospy.Subscriber("/clock", Clock, counter("clock"), queue_size=10),
                rospy.Subscriber(g + "model_states", ModelStates, counter("model_states"), queue_size=1),
                rospy.Subscriber(g + "link_states", LinkStates, counter("link_states"), queue_size=1),
                rospy.Subscriber(ns + "/joint_states", JointState, counter("joint_states"), queue_size=10)]
        deadline = time.time() + 20
        while time.time() < deadline and any(s.get_num_connections() == 0 for s in subs + pubs):
            time.sleep(0.05)
        world = rospy.ServiceProxy(g + "get_world_properties", GetWorldProperties)
        rospy.ServiceProxy(g + "unpause_physics", Empty)()
        time.sleep(0.5)
        t0, w0, c0 = world().sim_time, time.perf_counter(), cpu_seconds(node.pid)
        n0 = dict(counts)
        time.sleep(seconds)
        t1, w1, c1 = world().sim_time, time.perf_counter(), cpu_seconds(node.pid)
        rss = rss_mb(node.pid)
        rospy.ServiceProxy(g + "pause_physics", Empty)()
        for s in subs + pubs:
            s.unregister()
        steps, wall = (t1 - t0) / 0.001, w1 - w0
        return {"cpu_steps_per_s": steps / max(1e-9, c1 - c0), "wall_steps_per_s": steps / wall,
                "rtf": (t1 - t0) / wall, "cpu_load": (c1 - c0) / wall, "rss_mb": rss,
                "rates": {k: (counts[k] - n0[k]) / wall for k in counts}}
    finally:
        terminate(node)


def unit_node(args):
    master = Master()
    try:
        import rospy
        rospy.set_param("/use_sim_time", True)
        rospy.init_node("bench_node", disable_signals=True)
        seconds = args.seconds or 5.0
        # the node as it runs by default (roscpp publishing, the World stepping natively between
        # the hooks' due times), then publishing with rospy (~native_publishing false)
        out = {"throttled": run_node_once(seconds, 1000.0),
               "every_step": run_node_once(seconds, 0.0),
               "throttled_rospy": run_node_once(seconds, 1000.0, roscpp=False),
               "every_step_rospy": run_node_once(seconds, 0.0, roscpp=False)}
        out["pybullet"] = scene.run_pybullet(int(seconds * 2000), scene.scene_files())
        return out
    finally:
        master.close()


# ---- a robot with sensors against the same robot without: the step loop's due times (issue 33) -----
ARM_NS = "/sarm"
ARM_JOINTS = ["yaw", "shoulder", "elbow"]
SENSOR_LASER = """<link name="laser_link"><inertial><mass value="0.1"/><inertia ixx="1e-4" ixy="0" ixz="0"
  iyy="1e-4" iyz="0" izz="1e-4"/></inertial></link>
<joint name="laser_joint" type="fixed"><parent link="base"/><child link="laser_link"/>
  <origin xyz="0.15 0 0.15"/></joint>
<gazebo reference="laser_link"><sensor type="ray" name="laser"><update_rate>40</update_rate>
  <ray><scan><horizontal><samples>360</samples><resolution>1</resolution><min_angle>-3.14159</min_angle>
  <max_angle>3.14159</max_angle></horizontal></scan><range><min>0.1</min><max>10</max>
  <resolution>0.01</resolution></range></ray>
  <plugin name="laser" filename="libgazebo_ros_laser.so"><topicName>/sarm/scan</topicName>
  <frameName>laser_link</frameName></plugin></sensor></gazebo>
<gazebo reference="l3"><sensor type="imu" name="imu"><always_on>true</always_on><update_rate>200</update_rate>
  <plugin name="imu" filename="libgazebo_ros_imu_sensor.so"><topicName>/sarm/imu</topicName>
  <updateRateHZ>200</updateRateHZ><frameName>l3</frameName></plugin></sensor></gazebo>
"""


def sensor_arm_urdf(sensors):
    """The 3-joint arm of the control tests on effort joints, with (``sensors``) a 40 Hz 360-ray laser
    on its base and a 200 Hz IMU on its last link."""
    with open(os.path.join(ROOT, "src/modrob_sim/test/fixtures/control/arm_3dof.urdf")) as f:
        urdf = f.read().replace("PositionJointInterface", "EffortJointInterface").replace("/arm3", ARM_NS)
    return urdf.replace("</robot>", (SENSOR_LASER if sensors else "") + "</robot>")


def run_sensor_arm_once(seconds, sensors, subscribe, env=None):
    """The node as ``empty_world.launch real_time_factor:=0`` starts it (its world file, as fast as
    possible, no environment switches), the arm spawned and its controllers started through the
    services; simulated s per CPU s of the node over ``seconds`` of wall time."""
    import rospy
    from controller_manager_msgs.srv import LoadController, SwitchController
    from gazebo_msgs.srv import GetWorldProperties, SpawnModel
    from geometry_msgs.msg import Pose, Quaternion
    from sensor_msgs.msg import Imu, LaserScan
    node = subprocess.Popen([sys.executable, os.path.join(ROOT, "src/modrob_sim/scripts/gazebo"),
                             "_world_name:=worlds/empty.world", "_publish_rate:=100", "_real_time_factor:=0",
                             "_rtf_log_period:=0"],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        g = "/gazebo/"
        rospy.wait_for_service(g + "spawn_urdf_model", timeout=60)
        rospy.set_param(ARM_NS + "/joint_state_controller",
                        {"type": "joint_state_controller/JointStateController", "publish_rate": 50})
        names = ["joint_state_controller"]
        for j in ARM_JOINTS:
            rospy.set_param("%s/%s_controller" % (ARM_NS, j),
                            {"type": "effort_controllers/JointPositionController", "joint": j,
                             "pid": {"p": 100.0, "i": 10.0, "d": 5.0, "i_clamp": 5.0}})
            names.append("%s_controller" % j)
        ok = rospy.ServiceProxy(g + "spawn_urdf_model", SpawnModel)(
            "sarm", sensor_arm_urdf(sensors), "", Pose(orientation=Quaternion(0, 0, 0, 1)), "").success
        rospy.wait_for_service(ARM_NS + "/controller_manager/load_controller", timeout=30)
        load = rospy.ServiceProxy(ARM_NS + "/controller_manager/load_controller", LoadController)
        ok = ok and all(load(n).ok for n in names)
        ok = ok and rospy.ServiceProxy(ARM_NS + "/controller_manager/switch_controller", SwitchController)(
            names, [], 2, False, 0.0).ok
        if not ok:
            raise RuntimeError("building the sensor arm scene failed")
        got = {"scan": 0, "imu": 0}
        subs = []
        if sensors and subscribe:
            def count(key):
                return lambda _msg: got.__setitem__(key, got[key] + 1)
            subs = [rospy.Subscriber(ARM_NS + "/scan", LaserScan, count("scan")),
                    rospy.Subscriber(ARM_NS + "/imu", Imu, count("imu"))]
            deadline = time.time() + 20
            while time.time() < deadline and any(s.get_num_connections() == 0 for s in subs):
                time.sleep(0.05)
        world = rospy.ServiceProxy(g + "get_world_properties", GetWorldProperties)
        time.sleep(1.0)
        t0, w0, c0 = world().sim_time, time.perf_counter(), cpu_seconds(node.pid)
        n0 = dict(got)
        time.sleep(seconds)
        t1, w1, c1 = world().sim_time, time.perf_counter(), cpu_seconds(node.pid)
        for s in subs:
            s.unregister()
        wall = w1 - w0
        return {"sim_per_cpu": (t1 - t0) / max(1e-9, c1 - c0), "rtf": (t1 - t0) / wall,
                "cpu_load": (c1 - c0) / wall, "rates": {k: (got[k] - n0[k]) / wall for k in got}}
    finally:
        terminate(node)


def unit_sensor_arm(args):
    """The arm with and without its laser and IMU, nobody subscribed to the sensors (what a user
    who starts a robot and looks at nothing pays), then with both sensors subscribed."""
    master = Master()
    try:
        import rospy
        rospy.set_param("/use_sim_time", True)
        # this process does not subscribe to /clock: only the node and its robot are measured
        rospy.init_node("bench_sensor_arm", disable_signals=True, disable_rostime=True)
        seconds = args.seconds or 6.0
        return {"bare": run_sensor_arm_once(seconds, False, False),
                "sensors": run_sensor_arm_once(seconds, True, False),
                "sensors_subscribed": run_sensor_arm_once(seconds, True, True)}
    finally:
        master.close()


# ---- Bulbs and Slides: simulated seconds per wall second ----------------------------------------------
PACE_PROBE_S = 4.0


def unit_bulbs(scenario, args):
    """One ``bulbs_and_slides_demo`` run; the simulator node's CPU seconds are sampled while it
    runs, so that simulated s per node CPU s can be given beside simulated s per wall s: over the
    scenario's own wall time (its clock starts when the robots are ready, just before its "[2/"
    line) and over the whole run including start-up (whose simulated time, the world waiting for
    the robots and the scenario's nodes at real_time_factor 0, and the pace probe, are not the
    scenario's)."""
    import threading
    out = scratch_dir("modrob_bench_bas_")
    t0 = time.perf_counter()
    demo = os.path.join(ROOT, "src/modrob_motion/scripts/bulbs_and_slides_demo")
    # the scenario's pace: without the camera streams that make demo adds (their own processes)
    # --pace-probe: the simulator's own factor in the same world and run, the robots holding, measured
    # right after the pick-and-place: the reference that says whether the scenario keeps up
    proc = subprocess.Popen([demo, "--scenario", scenario, "--out", out, "--seed", str(args.rep),
                             "--no-streams", "--pace-probe", str(PACE_PROBE_S)],
                            stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    cpu = {}
    series = []         # (time.monotonic(), the node's CPU s)
    lines = {"stdout": [], "stderr": [], "started_at": None}

    def sample():
        while proc.poll() is None:
            pid = find_node(proc.pid)
            if pid:
                try:
                    cpu[pid] = cpu_seconds(pid)
                    series.append((time.monotonic(), sum(cpu.values())))
                except OSError:
                    pass
            time.sleep(0.1)

    def read(name, stream):
        for ln in stream:
            if name == "stdout" and ln.startswith("[2/") and lines["started_at"] is None:
                lines["started_at"] = time.monotonic()
            lines[name].append(ln)
    threads = [threading.Thread(target=sample, daemon=True),
               threading.Thread(target=read, args=("stdout", proc.stdout), daemon=True),
               threading.Thread(target=read, args=("stderr", proc.stderr), daemon=True)]
    for th in threads:
        th.start()
    try:
        proc.wait(timeout=900)
    finally:
        if proc.poll() is None:
            proc.kill()
    for th in threads:
        th.join(2)
    proc = subprocess.CompletedProcess(proc.args, proc.returncode, "".join(lines["stdout"]),
                                       "".join(lines["stderr"]))
    wall = time.perf_counter() - t0
    node_cpu = sum(cpu.values())
    path = os.path.join(out, "bulbs_and_slides_%s_result.yaml" % scenario)
    res = {}
    if os.path.exists(path):
        import yaml
        with open(path) as f:
            res = yaml.safe_load(f) or {}
    sim, scen_wall = res.get("sim_time", 0.0), res.get("wall_time", 0.0)
    alone = res.get("sim_alone_rtf")
    alone = alone if isinstance(alone, float) and alone > 0 and not math.isnan(alone) else None
    # the node's CPU over the scenario's wall time
    scen_cpu = None
    if lines["started_at"] is not None and scen_wall > 0 and series:
        scen_cpu = cpu_at(series, lines["started_at"] + scen_wall) - cpu_at(series, lines["started_at"])
    line = [ln for ln in proc.stdout.splitlines() if ln.startswith("RESULT")]
    # the pace while a bulb is gripped (the grasp's pad contacts) and over the rest of the run
    held_sim, held_wall = res.get("held_sim_time") or 0.0, res.get("held_wall_time") or 0.0
    free_sim, free_wall = sim - held_sim, scen_wall - held_wall
    return {"held_per_wall": held_sim / held_wall if held_wall > 0 else None,
            "free_per_wall": free_sim / free_wall if held_wall > 0 and free_wall > 0 else None,
            "success": bool(proc.returncode == 0 and res.get("success")), "sim_time": sim,
            "scenario_wall": scen_wall, "wall_incl_startup": wall,
            "sim_per_wall": sim / scen_wall if scen_wall > 0 else 0.0, "sim_alone_per_wall": alone,
            "sim_per_wall_incl_startup": sim / wall if wall > 0 else 0.0, "node_cpu_s": node_cpu,
            "sim_per_node_cpu_incl_startup": sim / node_cpu if node_cpu > 0 else 0.0,
            "scenario_node_cpu_s": scen_cpu,
            # how late joint_states reached the scenario at worst (simulated s): while it waits for
            # them the simulation runs on, so a late stream adds simulated time of robots holding
            "js_lag": res.get("js_lag"),
            "sim_per_node_cpu": sim / scen_cpu if scen_cpu else None,
            "result": line[-1] if line else (proc.stdout[-300:] + proc.stderr[-300:])}


def cpu_at(series, t):
    """CPU s at time.monotonic() ``t`` from samples (time, CPU s), interpolated linearly."""
    prev = None
    for ts, c in series:
        if ts >= t:
            if prev is None:
                return c
            return prev[1] + (c - prev[1]) * (t - prev[0]) / max(1e-9, ts - prev[0])
        prev = (ts, c)
    return series[-1][1]


# ---- start-up: roslaunch -> first /clock ------------------------------------------------------------
PEER_LAUNCH = """<launch><param name="/use_sim_time" value="false"/>
  <node pkg="rostopic" type="rostopic" name="clock_pub"
        args="pub -r 10 /clock rosgraph_msgs/Clock '{clock: {secs: 1}}'"/>
</launch>"""


def first_clock(cmd, timeout=90.0):
    """Wall seconds from starting ``cmd`` (a roslaunch with its own master on a free port) to the
    first /clock message received here."""
    import signal
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % port)
    t0 = time.monotonic()
    proc = subprocess.Popen(cmd + ["-p", str(port)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        probe = subprocess.run([sys.executable, "-c", CLOCK_PROBE, str(timeout)], env=env,
                               capture_output=True, text=True, timeout=timeout + 10)
        if probe.returncode != 0:
            raise RuntimeError("no /clock from %s: %s" % (" ".join(cmd), probe.stderr[-300:]))
        return float(probe.stdout.split()[-1]) - t0
    finally:
        try:
            os.killpg(proc.pid, signal.SIGINT)
            proc.wait(20)
        except (subprocess.TimeoutExpired, ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)


# the probe prints time.monotonic() (CLOCK_MONOTONIC, the same in every process) when the first /clock arrives
CLOCK_PROBE = r"""
import sys, time, socket, xmlrpc.client
import rosgraph
deadline = time.time() + float(sys.argv[1])
while not rosgraph.is_master_online():
    if time.time() > deadline: sys.exit(2)
    time.sleep(0.02)
import rospy
from rosgraph_msgs.msg import Clock
rospy.init_node("first_clock_probe", anonymous=True, disable_signals=True, disable_rostime=True)
got = []
sub = rospy.Subscriber("/clock", Clock, lambda m: got.append(time.monotonic()) if not got else None)
while not got:
    if time.time() > deadline: sys.exit(3)
    time.sleep(0.005)
print(got[0])
"""


def unit_startup(_args):
    peer = os.path.join(scratch_dir("modrob_bench_launch_"), "peer.launch")
    with open(peer, "w") as f:
        f.write(PEER_LAUNCH)
    ours = first_clock(["roslaunch", "modrob_sim", "empty_world.launch", "gui:=false"])
    base = first_clock(["roslaunch", peer])
    return {"ours_s": ours, "peer_s": base}


# ---- memory: the node's RSS with the 6-DoF scene ----------------------------------------------------
PYBULLET_RSS = r"""
import sys, json
sys.path.insert(0, sys.argv[1])
import physics_core as scene, pybullet as p
files = scene.scene_files()
p.connect(p.DIRECT)
p.loadURDF(files["table"], useFixedBase=True); p.loadURDF(files["arm"], useFixedBase=True)
for x, y in scene.OBJECTS:
    p.loadURDF(files["can"], basePosition=(x, y, 0.8))
for _ in range(1000):
    p.stepSimulation()
for ln in open("/proc/self/status"):
    if ln.startswith("VmRSS:"):
        print(int(ln.split()[1]) / 1024.0)
"""


def unit_rss(args):
    master = Master()
    try:
        import rospy
        rospy.set_param("/use_sim_time", True)
        rospy.init_node("bench_rss", disable_signals=True)
        from std_srvs.srv import Empty
        node = start_node()
        try:
            build_scene()
            rospy.ServiceProxy("/gazebo/unpause_physics", Empty)()
            time.sleep(args.seconds or 2.0)
            ours = rss_mb(node.pid)
        finally:
            terminate(node)
    finally:
        master.close()
    peer = float(subprocess.run([sys.executable, "-c", PYBULLET_RSS, HERE], capture_output=True, text=True,
                                check=True).stdout.split()[-1])
    return {"ours_mb": ours, "peer_mb": peer}


# ---- KDL FK of a 3700-point trajectory -----------------------------------------------------------------
def unit_kdl_fk(_args):
    import numpy as np
    from modrob_kinematics.kdl_urdf import KinematicChain
    rng = np.random.default_rng(0)
    n = 3700
    traj = np.array(scene.Q_HOLD) + 0.5 * np.sin(np.linspace(0, 2 * math.pi, n)[:, None] * (1 + np.arange(N)))
    traj += 0.01 * rng.standard_normal(traj.shape)
    chain = KinematicChain.from_urdf_string(scene.arm_urdf(), "base", "link%d" % N)
    c0 = time.process_time()
    ours = [chain.fk_position(list(q)) for q in traj]
    ours_cpu = time.process_time() - c0
    import pybullet as p
    cid = p.connect(p.DIRECT)
    try:
        f = scene.scene_files()["arm"]
        arm = p.loadURDF(f, useFixedBase=True, basePosition=(0, 0, 0))
        jidx = [i for i in range(p.getNumJoints(arm)) if p.getJointInfo(arm, i)[2] == p.JOINT_REVOLUTE]
        c0 = time.process_time()
        theirs = []
        for q in traj:
            for i, v in zip(jidx, q):
                p.resetJointState(arm, i, float(v))
            theirs.append(p.getLinkState(arm, jidx[-1], computeForwardKinematics=True)[4])
        peer_cpu = time.process_time() - c0
    finally:
        p.disconnect(cid)
    # both give link6's frame origin; ours relative to "base", PyBullet's in its world (base at the
    # fixed joint's origin, z = TABLE_TOP): compare after removing that offset
    diff = max(math.dist(a, (b[0], b[1], b[2] - scene.TABLE_TOP)) for a, b in zip(ours, theirs))
    return {"points": n, "ours_points_per_s": n / ours_cpu, "peer_points_per_s": n / peer_cpu,
            "max_diff_m": diff}


# ---- a TurtleBot3-class robot driving (issue 35) -----------------------------------------------------
MOBILE_URDF = os.path.join(ROOT, "src/modrob_sim/test/fixtures/drives/diff_bot.urdf")


#: a depth camera on the base, as a TurtleBot3 waffle declares its own (openni_kinect plugin, its
#: topic names) at a common RealSense mode: 640x480 at 30 Hz
DEPTH_CAMERA = """
  <gazebo reference="base_link">
    <sensor type="depth" name="bench_depth">
      <pose>0.06 0 0.1 0 0 0</pose>
      <update_rate>30</update_rate>
      <camera>
        <horizontal_fov>1.3439</horizontal_fov>
        <image><width>640</width><height>480</height><format>R8G8B8</format></image>
        <clip><near>0.03</near><far>100</far></clip>
      </camera>
      <plugin name="camera_controller" filename="libgazebo_ros_openni_kinect.so">
        <updateRate>30.0</updateRate>
        <cameraName>camera</cameraName>
        <frameName>camera_rgb_optical_frame</frameName>
        <imageTopicName>rgb/image_raw</imageTopicName>
        <depthImageTopicName>depth/image_raw</depthImageTopicName>
        <pointCloudTopicName>depth/points</pointCloudTopicName>
        <pointCloudCutoff>0.4</pointCloudCutoff>
      </plugin>
    </sensor>
  </gazebo>
</robot>"""


def mobile_robot_urdf(plugins, depth=False):
    """Our TurtleBot3-style robot (360-ray lidar at 5 Hz, IMU at 200 Hz, diff drive); without its
    <plugin> elements for the reference; with ``depth`` also DEPTH_CAMERA."""
    import re
    with open(MOBILE_URDF) as f:
        text = f.read()
    if depth:
        text = text.replace("</robot>", DEPTH_CAMERA)
    return text if plugins else re.sub(r"<plugin\b.*?</plugin>", "", text, flags=re.S)


def run_mobile_once(seconds, plugins, depth=False, watch_camera=True):
    """The /gazebo node (real_time_factor 0) with the robot driving a circle (0.2 m/s, 0.4 rad/s),
    /scan, /imu and /odom subscribed: simulated s per wall s over ``seconds``. ``depth``: with
    the depth camera, its point cloud subscribed (the renderer the node starts for it runs), timed
    from its first cloud; with ``watch_camera`` False nobody subscribes to it (no renderer runs)."""
    import rospy
    from gazebo_msgs.srv import GetWorldProperties, SpawnModel
    from geometry_msgs.msg import Pose, Quaternion, Twist
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import Imu, LaserScan, PointCloud2
    from std_srvs.srv import Empty
    node = start_node()
    try:
        g = "/gazebo/"
        rospy.wait_for_service(g + "spawn_urdf_model", timeout=60)
        if not rospy.ServiceProxy(g + "spawn_urdf_model", SpawnModel)(
                "bot", mobile_robot_urdf(plugins, depth), "", Pose(orientation=Quaternion(0, 0, 0, 1)),
                "").success:
            raise RuntimeError("spawning the mobile robot failed")
        counts = {"scan": 0, "imu": 0, "odom": 0, "points": 0}

        def counter(key):
            def cb(_msg):
                counts[key] += 1
            return cb
        subs = [rospy.Subscriber("/scan", LaserScan, counter("scan"), queue_size=10),
                rospy.Subscriber("/imu", Imu, counter("imu"), queue_size=100),
                rospy.Subscriber("/odom", Odometry, counter("odom"), queue_size=10)]
        if depth and watch_camera:
            subs.append(rospy.Subscriber("/camera/depth/points", PointCloud2, counter("points"), queue_size=1,
                                         buff_size=2 ** 25))
        cmd = rospy.Publisher("/cmd_vel", Twist, queue_size=1, latch=True)
        twist = Twist()
        twist.linear.x, twist.angular.z = 0.2, 0.4
        deadline = time.time() + 20
        waiting = [cmd] + subs if plugins else []
        while time.time() < deadline and any(s.get_num_connections() == 0 for s in waiting):
            time.sleep(0.05)
        cmd.publish(twist)
        world = rospy.ServiceProxy(g + "get_world_properties", GetWorldProperties)
        rospy.ServiceProxy(g + "unpause_physics", Empty)()
        time.sleep(0.5)
        deadline = time.time() + 180
        while depth and watch_camera and counts["points"] == 0 and time.time() < deadline:
            time.sleep(0.1)         # the renderer starting (Xvfb, RViz): not part of the window
        t0, w0, c0 = world().sim_time, time.perf_counter(), cpu_seconds(node.pid)
        n0 = dict(counts)
        time.sleep(seconds)
        t1, w1, c1 = world().sim_time, time.perf_counter(), cpu_seconds(node.pid)
        rospy.ServiceProxy(g + "pause_physics", Empty)()
        for s in subs + [cmd]:
            s.unregister()
        sim, wall = t1 - t0, w1 - w0
        return {"rtf": sim / wall, "sim_per_cpu": sim / max(1e-9, c1 - c0), "cpu_load": (c1 - c0) / wall,
                "rates": {k: (counts[k] - n0[k]) / sim for k in counts}}
    finally:
        terminate(node)


def unit_mobile(args):
    """Ours: the robot with its plugins; the peer: the same robot without them (the physics and the
    node alone), one after the other on the same master."""
    import rospy
    master = Master()
    try:
        rospy.init_node("bench_mobile", anonymous=True, disable_signals=True)
        seconds = args.seconds or 5.0
        return {"ours": run_mobile_once(seconds, True), "reference": run_mobile_once(seconds, False),
                "depth": run_mobile_once(seconds, True, depth=True),
                "depth_unwatched": run_mobile_once(seconds, True, depth=True, watch_camera=False)}
    finally:
        master.close()


# ---- the scenario launches' pace: simulated s per wall s at real_time_factor 0 -------------------------
#: scenario -> (roslaunch arguments, topics a demo's nodes listen to: (name, type)); the sensors
#: and controllers run as in the demo, the launch's own nodes included; no GUI, no renderer
DEMO_LAUNCHES = {
    "polaris": (["polaris_description", "polaris.launch", "gui:=false", "velodyne:=true"],
                [("/velodyne_points2", "sensor_msgs/PointCloud2"), ("/imu", "sensor_msgs/Imu"),
                 ("/fix", "sensor_msgs/NavSatFix"), ("/joint_states", "sensor_msgs/JointState")]),
    "katana": (["katana_sim", "katana_stack.launch", "gui:=false", "exit_when_done:=false?"], []),
    "ptrz": (["ptrz_camera", "ptrz.launch", "gui:=false", "images:=false", "cameras:=3", "world:=indoor"],
             [("/ptrz%d/joint_states" % i, "sensor_msgs/JointState") for i in (1, 2, 3)]),
}
#: scenarios measured over their own task instead of a window of wall time: (latched topic and type
#: whose first message starts it, the launch argument naming the result file whose writing ends it).
#: The Katana's stacking takes ~50 simulated s; a fixed window would cover more or less of it, and of
#: the idle arm after it, depending on the pace
DEMO_SPANS = {"katana": ("/katana/planned_path", "visualization_msgs/MarkerArray", "result_file")}


def _node_name(pid):
    """The ROS node name of a process (its ``__name:=`` argument), else its command."""
    try:
        with open("/proc/%d/cmdline" % pid, "rb") as f:
            argv = [a.decode(errors="replace") for a in f.read().split(b"\0") if a]
    except OSError:
        return None
    for a in argv:
        if a.startswith("__name:="):
            return a[len("__name:="):]
    return os.path.basename(argv[1] if len(argv) > 1 and "python" in argv[0] else argv[0]) if argv else None


def unit_demo_pace(scenario, args):
    """``roslaunch`` of the scenario's launch file with ``real_time_factor:=0`` on a master of its
    own (the workspace this process runs in: its ROS_PACKAGE_PATH), the demo's topics subscribed;
    the simulated time over the wall time, and over the CPU time of every process of the launch
    (also per node), of: the scenario's task where DEMO_SPANS names one (start to result), else
    ``seconds`` of wall time from 3 s after every topic of the demo has sent its first message
    (the robot is in and its sensors and controllers run: a loaded machine can take seconds to
    spawn it, and the empty world's pace before that is no figure of the demo)."""
    import threading
    cmd, topics = DEMO_LAUNCHES[scenario]
    span = DEMO_SPANS.get(scenario)
    # "name:=value?": only where the launch file declares the argument (older versions of it too)
    launch_file = subprocess.run(["rospack", "find", cmd[0]], capture_output=True, text=True).stdout.strip()
    with open(os.path.join(launch_file, "launch", cmd[1])) as f:
        text = f.read()
    cmd = [a for a in cmd if not a.endswith("?")] + \
        [a[:-1] for a in cmd if a.endswith("?") and 'name="%s"' % a.split(":=")[0] in text]
    tmp = scratch_dir("bench_%s_" % scenario)
    result_file = os.path.join(tmp, "result.yaml")
    if span:
        cmd.append("%s:=%s" % (span[2], result_file))
    port = free_port()
    os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % port
    launch = subprocess.Popen(["roslaunch", "-p", str(port)] + cmd + ["real_time_factor:=0"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        import rosgraph
        import roslib.message
        import rospy
        from gazebo_msgs.srv import GetWorldProperties
        deadline = time.time() + 120
        while not rosgraph.is_master_online():
            if time.time() > deadline or launch.poll() is not None:
                raise RuntimeError("%s: the master did not come up" % scenario)
            time.sleep(0.2)
        rospy.init_node("bench_demo_pace", anonymous=True, disable_signals=True, disable_rostime=True)
        counts = {name: 0 for name, _ in topics}
        lock = threading.Lock()

        def counter(name):
            def cb(_msg):
                with lock:
                    counts[name] += 1
            return cb
        subs = [rospy.Subscriber(name, roslib.message.get_message_class(kind), counter(name), queue_size=2,
                                 buff_size=2 ** 22)
                for name, kind in topics]
        rospy.wait_for_service("/gazebo/get_world_properties", timeout=120)
        world = rospy.ServiceProxy("/gazebo/get_world_properties", GetWorldProperties)
        if span:
            rospy.wait_for_message(span[0], roslib.message.get_message_class(span[1]), timeout=300)
        else:
            while world().sim_time <= 0.0 or not all(counts.values()):
                if time.time() > deadline or launch.poll() is not None:
                    raise RuntimeError("%s: no message yet on %s within 120 s of the launch"
                                       % (scenario, ", ".join(n for n, c in counts.items() if not c)
                                          or "/clock (simulated time did not start)"))
                time.sleep(0.1)
            time.sleep(3.0)
        pids = descendants(launch.pid)
        node = find_node(launch.pid)
        t0, w0 = world().sim_time, time.perf_counter()
        c0 = {p: _cpu(p) for p in pids}
        th0 = thread_cpu_seconds(node) if node else {}
        n0 = dict(counts)
        if span:
            end = time.time() + 600
            while not os.path.exists(result_file):        # the result, written at the end of the task
                if time.time() > end or launch.poll() is not None:
                    raise RuntimeError("%s: no result file %s" % (scenario, result_file))
                time.sleep(0.01)
        else:
            time.sleep(args.seconds or 10.0)
        t1, w1 = world().sim_time, time.perf_counter()
        c1 = {p: _cpu(p) for p in pids}
        th1 = thread_cpu_seconds(node) if node else {}
        for sub in subs:
            sub.unregister()
        sim, wall, cpu = t1 - t0, w1 - w0, sum(c1[p] - c0[p] for p in pids)
        per_node = {}
        for p in pids:
            name = _node_name(p) or str(p)
            per_node[name] = per_node.get(name, 0.0) + c1[p] - c0[p]
        busiest = sorted(per_node.items(), key=lambda kv: -kv[1])
        res = {"sim_per_wall": sim / wall, "sim_per_cpu": sim / max(1e-9, cpu),
               "cpu_load": cpu / wall, "sim_time": sim, "wall": wall, "cpu": cpu,
               "cpu_per_sim_s": {k: round(v / sim, 5) for k, v in busiest if v > 0 and sim > 0},
               "rates": {k: (counts[k] - n0[k]) / sim if sim > 0 else 0.0 for k in counts}}
        if node and sim > 0:
            # the simulator node's busiest thread (the simulation loop: physics, plugins, what it
            # publishes), which sets the pace, apart from the node's other threads (roscpp's and
            # rospy's transport, the sensors' packing, the publishing sender)
            spent = sorted((th1[tid] - th0.get(tid, 0.0) for tid in th1), reverse=True)
            res["node_loop_thread_per_sim_s"] = round(spent[0] / sim, 5) if spent else None
            res["node_other_threads_per_sim_s"] = round(sum(spent[1:]) / sim, 5)
        if span:
            with open(result_file) as f:
                res["result"] = f.readline().strip()        # "success: true"
        return res
    finally:
        stop(launch, 30)             # SIGINT to roslaunch's group, as Ctrl-C
        shutil.rmtree(tmp, ignore_errors=True)


def _cpu(pid):
    try:
        return cpu_seconds(pid)
    except OSError:
        return 0.0


UNITS = {"physics_core": unit_physics_core, "node": unit_node, "mobile": unit_mobile,
         "bulbs_one": lambda a: unit_bulbs("one_robot", a),
         "bulbs_two": lambda a: unit_bulbs("two_robots", a),
         "startup": unit_startup, "rss": unit_rss, "kdl_fk": unit_kdl_fk, "sensor_arm": unit_sensor_arm,
         "polaris_pace": lambda a: unit_demo_pace("polaris", a),
         "katana_pace": lambda a: unit_demo_pace("katana", a),
         "ptrz_pace": lambda a: unit_demo_pace("ptrz", a)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("unit", choices=sorted(UNITS))
    ap.add_argument("--seconds", type=float, default=0.0)
    ap.add_argument("--rep", type=int, default=0)
    ap.add_argument("--json", default=None,
                    help="also write the result to this file (the sweep runner reads it)")
    args = ap.parse_args()
    res = UNITS[args.unit](args)
    res["load_avg"] = os.getloadavg()[0]
    print(json.dumps(res))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(res, fh)


if __name__ == "__main__":
    main()

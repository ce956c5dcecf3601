"""``bulbs_and_slides_demo``: the whole scenario headless, as ``make demo`` runs it.

Starts its own ROS master on a free port, launches the simulation (bulbs_and_slides.launch with
run:=false, real_time_factor 0 = as fast as possible, no GUI), runs the pick-and-place in this
process, prints progress and one RESULT line, and writes under --out:
    bulbs_and_slides_<scenario>_ee.bag       end-effector trajectory (geometry_msgs/PointStamped)
    bulbs_and_slides_<scenario>_joints.png   commanded vs measured joint angles
    bulbs_and_slides_<scenario>_result.yaml  the result in numbers
    bulbs_and_slides_<scenario>_sim.log      the simulator's output
    bulbs_and_slides_<scenario>_frame.png    a frame of the orthographic camera stream (end of the run)
    bulbs_and_slides_<scenario>_views.avi    the pick-and-place from the top, front, right and
                                             orthographic views, tiled 2x2 (MJPG)
    bulbs_and_slides_<scenario>_camera/      each view's video and frame (camera_renderer's files)
    bulbs_and_slides_<scenario>_camera.log   the renderer's output
The camera streams (rviz_camera_stream.launch, headless) are on unless --no-streams;
their files are checked (decodable by OpenCV) before the demo reports success.
Exit status 0 only on success.
"""
import argparse
import os
import sys
import threading
import time

import yaml

from modrob_motion.bulbs_and_slides import ScenarioError
from modrob_motion.bulbs_and_slides.layout import Layout, SCENARIOS
from modrob_msgs.errors import ModrobError
from modrob_sim import scenario_launch


def wait_for_master(timeout=30.0):
    import rosgraph
    deadline = time.time() + timeout
    while time.time() < deadline:
        if rosgraph.is_master_online():
            return True
        time.sleep(0.2)
    return False


def wait_for_param(name, timeout=60.0):
    import rosgraph
    master = rosgraph.Master("/bulbs_and_slides_demo")
    deadline = time.time() + timeout
    while time.time() < deadline:
        try:
            if master.hasParam(name):
                return True
        except OSError:
            pass
        time.sleep(0.2)
    return False


def start_simulation(scenario, log_path, gui=False, rtf="0", grip_force=3.0, port=None, gains="tuned"):
    log = open(log_path, "w")
    proc = scenario_launch.start(["modrob_motion", "bulbs_and_slides.launch", "scenario:=%s" % scenario,
                                  "run:=false", "gui:=%s" % ("true" if gui else "false"),
                                  "real_time_factor:=%s" % rtf, "grip_force:=%s" % grip_force,
                                  "gains:=%s" % gains], log, port=port)
    return proc, log


def stop_simulation(proc, log):
    scenario_launch.stop(proc, grace=20.0)
    log.close()


def stop_all(streams, proc, log):
    if streams is not None:
        streams.stop()
    stop_simulation(proc, log)


def _plot_two_robot_paths(sc, layout, path):
    from modrob_motion.bulbs_and_slides.paths_plot import plot_paths
    paths = {}
    for rid in sc.recorder.rows:
        t, _, _, ee, _ = sc.recorder.arrays(rid)
        paths[rid] = (t, ee)
    mon = getattr(sc, "clearance", None)
    closest = None
    if mon is not None and mon.samples:
        closest = (mon.closest[0], "modrob0 %s, modrob1 %s" % (mon.closest[1], mon.closest[2]))
    plot_paths(path, layout, paths, title="Bulbs and Slides (two robots): grasp-centre paths",
               closest=closest)
    print("wrote %s" % path, flush=True)


def main(argv=None):
    p = argparse.ArgumentParser(prog="bulbs_and_slides_demo", description=__doc__.splitlines()[0])
    p.add_argument("--scenario", choices=SCENARIOS, default="one_robot")
    p.add_argument("--out", default="out")
    p.add_argument("--gui", action="store_true", help="open RViz as well")
    p.add_argument("--real-time-factor", default="0", help="0 = as fast as possible (default)")
    p.add_argument("--jitter", type=float, default=0.0, help="shift the bulb by up to this much (m), seeded")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--grip-force", type=float, default=3.0)
    p.add_argument("--gains", choices=("tuned", "computed"), default="tuned",
                   help="arm PID gains: tune_pid's table (default) or computed from the inertias")
    p.add_argument("--arm-speed", type=float, default=0.5, help="joint speed of the free moves (rad/s)")
    p.add_argument("--motion", choices=("trajectory", "stream"), default="trajectory",
                   help="how the arm's motions reach the simulator: each segment to a "
                        "JointTrajectoryController (default) or set-points streamed through motion_publisher")
    p.add_argument("--no-streams", action="store_true",
                   help="no camera streams (frame and video of the principal views)")
    p.add_argument("--stream-rate", type=float, default=5.0, help="frames per second of each view")
    p.add_argument("--stream-size", default="320x240", help="WIDTHxHEIGHT of each view")
    p.add_argument("--pace-probe", type=float, default=0.0, metavar="S",
                   help="after the run, measure the simulator's real-time factor for S wall seconds with the "
                        "robots holding (the reference for the run's own; benchmarks)")
    args = p.parse_args(argv)
    if args.pace_probe < 0:
        p.error("--pace-probe must be >= 0 seconds, got %g" % args.pace_probe)
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, "bulbs_and_slides_%s" % args.scenario)
    try:
        layout = Layout.load(args.scenario)
    except ModrobError as exc:
        print("bulbs_and_slides_demo: %s" % exc, file=sys.stderr)
        return 2
    print("bulbs_and_slides_demo: %s, starting the simulation (log: %s_sim.log)" % (args.scenario, stem),
          flush=True)
    scenario_launch.sigterm_as_exit()
    proc, log = start_simulation(args.scenario, stem + "_sim.log", args.gui, args.real_time_factor,
                                 args.grip_force, gains=args.gains)
    result = None
    streams = None if args.no_streams else make_streams(args, stem)
    stream_files = None
    stopping = None
    try:
        if not wait_for_master() or not wait_for_param("/use_sim_time"):
            raise ScenarioError("the simulation did not start: see %s_sim.log" % stem)
        import rospy
        from modrob_motion.bulbs_and_slides.scenario import Scenario
        rospy.init_node("bulbs_and_slides_demo", disable_signals=True)
        if streams is not None:
            streams.start(stem + "_camera.log")
            print("bulbs_and_slides_demo: camera streams %s starting (log: %s_camera.log)"
                  % (", ".join(streams.views), stem), flush=True)
            streams.wait_ready()
        sc = Scenario(layout, jitter=args.jitter, seed=args.seed, arm_speed=args.arm_speed,
                      motion=args.motion)
        result = sc.run_two_robots() if args.scenario == "two_robots" else sc.run_one_robot()
        sc.stream_stats(result)
        if args.pace_probe > 0:
            result.sim_alone_rtf = sc.measure_pace(args.pace_probe)
        if streams is not None:
            stream_files = streams.finish()
            for path in stream_files:
                print("wrote %s" % path, flush=True)
        # what is left needs no simulation: the streams' and roslaunch's teardown (2-3 s of wall
        # time) run while the bag and the plots are written
        stopping = threading.Thread(target=stop_all, args=(streams, proc, log), name="stop_simulation")
        streams = None
        stopping.start()
        if sc.recorder and sc.recorder.rows:
            n = sc.recorder.write_bag(stem + "_ee.bag")
            names = {rid: r.info.arm_joints for rid, r in sc.robots.items()}
            sc.recorder.plot_joints(stem + "_joints.png", names, title="Bulbs and Slides (%s): commanded vs "
                                    "measured joint angles" % args.scenario)
            print("wrote %s_ee.bag (%d end-effector points) and %s_joints.png" % (stem, n, stem), flush=True)
            if args.scenario == "two_robots":
                _plot_two_robot_paths(sc, layout, stem + "_paths.png")
    except ModrobError as exc:
        print("bulbs_and_slides_demo: %s" % exc, file=sys.stderr, flush=True)
    finally:
        if stopping is None:
            stop_all(streams, proc, log)
        else:
            stopping.join()
    if result is None:
        print("RESULT %s: FAILURE -- the scenario did not run (see above)" % args.scenario, flush=True)
        return 1
    with open(stem + "_result.yaml", "w") as fh:
        yaml.safe_dump(dict(result.as_dict(), scenario=args.scenario, jitter=args.jitter, seed=args.seed), fh)
    print(result.line(args.scenario), flush=True)
    if streams is not None and stream_files is None:
        print("RESULT %s: FAILURE -- the camera streams' frame and video were not written (see above)"
              % args.scenario, flush=True)
        return 1
    return 0 if result.success else 1


def make_streams(args, stem):
    """The camera streams of the run (see camera_streams.CameraStreams)."""
    from modrob_motion.bulbs_and_slides.camera_streams import CameraStreams
    try:
        width, height = (int(v) for v in args.stream_size.lower().split("x"))
    except ValueError:
        raise SystemExit("bulbs_and_slides_demo: --stream-size must be WIDTHxHEIGHT, got %r"
                         % args.stream_size)
    return CameraStreams(stem + "_camera", stem, rate=args.stream_rate, width=width, height=height,
                         f=width * 200.0 / 320.0)


def node_main():
    """The ``bulbs_and_slides`` node (bulbs_and_slides.launch run:=true): runs the scenario on the
    simulation the launch file started. ~scenario, ~layout_file, ~result_file, ~jitter, ~seed,
    ~motion (trajectory | stream, see Scenario), ~exit_when_done (end the launch after the RESULT
    line, modrob_sim.end_launch)."""
    import rospy
    from modrob_motion.bulbs_and_slides.scenario import Scenario
    from modrob_sim.end_launch import finish_scenario
    rospy.init_node("bulbs_and_slides")
    scenario = rospy.get_param("~scenario", "one_robot")
    try:
        layout = Layout.load(scenario, rospy.get_param("~layout_file", "") or None)
        sc = Scenario(layout, log=rospy.loginfo, jitter=float(rospy.get_param("~jitter", 0.0)),
                      seed=int(rospy.get_param("~seed", 0)), motion=rospy.get_param("~motion", "trajectory"))
        result = sc.run_two_robots() if scenario == "two_robots" else sc.run_one_robot()
        sc.stream_stats(result)
        sc.release()        # motion_publisher (and so motion_terminal) drives the arms again
    except ModrobError as exc:
        if rospy.is_shutdown():     # Ctrl-C, or the launch ending: the user stopped it, nothing broke
            rospy.logwarn("bulbs_and_slides: stopped before the end (%s): no RESULT", exc)
        else:
            rospy.logerr("bulbs_and_slides: %s", exc)
        return 1
    (rospy.loginfo if result.success else rospy.logerr)(result.line(scenario))
    path = rospy.get_param("~result_file", "")
    if path:
        with open(path, "w") as fh:
            yaml.safe_dump(dict(result.as_dict(), scenario=scenario), fh)
    finish_scenario(rospy.loginfo, rospy.get_param("~exit_when_done", False), rospy.is_shutdown)
    return 0 if result.success else 1

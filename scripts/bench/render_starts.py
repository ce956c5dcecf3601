#!/usr/bin/env python3
"""Start camera_renderer many times and count the starts that crash: a stress check for the start-up
of the renderer (panels created, resized and shown while RViz already renders) that a single test
run only hits now and then.

Each start: a private ROS master, a static tf frame per camera, camera_renderer with N cameras of
the given sizes (all in one process, as rviz_camera_stream.launch or ptrz.launch run it); the start
counts as good once every camera has published an image, as a crash if the renderer ends before
(its exit status and the last lines of its output are printed).
  python3 scripts/bench/render_starts.py [--starts 30] [--pixels gl] [--sizes 640x360,320x128,...]
"""
import argparse
import os
import sys
import time

from procs import free_port, scratch_dir, start, stop

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT_SIZES = "640x360,640x360,640x360,640x360,640x360,320x128,320x128,320x128"


def parse_sizes(text):
    sizes = []
    for item in text.split(","):
        try:
            w, h = (int(v) for v in item.lower().split("x"))
        except ValueError:
            raise SystemExit("--sizes: %r is not WIDTHxHEIGHT" % item)
        if w <= 0 or h <= 0:
            raise SystemExit("--sizes: %r must be positive" % item)
        sizes.append((w, h))
    return sizes


def camera_info(w, h, frame):
    from sensor_msgs.msg import CameraInfo
    msg = CameraInfo()
    msg.header.frame_id = frame
    msg.width, msg.height = w, h
    f = w / 2.0
    msg.K = [f, 0, w / 2.0, 0, f, h / 2.0, 0, 0, 1]
    msg.P = [f, 0, w / 2.0, 0, 0, f, h / 2.0, 0, 0, 0, 1, 0]
    return msg


def one_start(index, args, sizes, env, logdir):
    """(ok, seconds, message, ended) of one renderer start (and its resizes, with --resizes); ended:
    the renderer died (a crash) rather than being slow."""
    import rospy
    from sensor_msgs.msg import CameraInfo, Image
    cams = ["{name: s%d, frame: stress%d, image: /stress/s%d/image, width: %d, height: %d, fx: %g}"
            % (i, i, i, w, h, w / 2.0) for i, (w, h) in enumerate(sizes)]
    if args.resizes:
        # one more camera whose CameraInfo (so its panel's size) alternates between two sizes
        cams.append("{name: r, camera_info: /stress/r/camera_info, image: /stress/r/image}")
    log = os.path.join(logdir, "renderer_%03d.log" % index)
    prefix = ["--prefix", args.prefix] if args.prefix else []
    cmd = ["rosrun"] + prefix + ["modrob_viz", "camera_renderer", "__name:=stress_renderer",
                                 "_rate:=%g" % args.rate, "_pixels:=%s" % args.pixels,
                                 "_cameras:=[%s]" % ", ".join(cams)]
    if args.sim:
        # and the world's camera sensor, added while it runs (the renderer draws the sensors only
        # when told where they register: the simulator's own renderer is not started here)
        cmd.append("_sensors_param:=/gazebo/camera_sensors")
    renderer = start(cmd, env, log)
    got = set()
    last_r = [None]

    def on_r(msg):
        last_r[0] = (msg.width, msg.height)
        got.add("r")
    subs = [rospy.Subscriber("/stress/s%d/image" % i, Image, lambda _m, i=i: got.add(i), queue_size=1)
            for i in range(len(sizes))]
    want = set(range(len(sizes)))
    info_pub = None
    if args.resizes:
        subs.append(rospy.Subscriber("/stress/r/image", Image, on_r, queue_size=1))
        info_pub = rospy.Publisher("/stress/r/camera_info", CameraInfo, queue_size=1, latch=True)
        info_pub.publish(camera_info(*args.resize_sizes[0] + ("stress0",)))
        want.add("r")
    done = 0
    t0 = time.time()
    timeout = args.timeout + 2.0 * args.resizes
    try:
        while time.time() - t0 < timeout:
            if renderer.poll() is not None:
                break
            if want <= got:
                if done >= args.resizes:
                    return True, time.time() - t0, "", False
                if last_r[0] == args.resize_sizes[done % 2]:    # the image has the size asked: resize
                    done += 1
                    info_pub.publish(camera_info(*args.resize_sizes[done % 2] + ("stress0",)))
            time.sleep(0.02)
        code = renderer.poll()
        with open(log) as f:
            tail = [line.rstrip() for line in f.readlines()[-6:]]
        what = ("ended with status %d" % code) if code is not None else \
            ("gave images from %d of %d cameras, %d of %d resizes in %.0f s"
             % (len(got), len(want), done, args.resizes, timeout))
        msg = ("after %d resizes: " % done) + what + "\n    " + "\n    ".join(tail)
        return False, time.time() - t0, msg, code is not None
    finally:
        for sub in subs:
            sub.unregister()
        if info_pub is not None:
            info_pub.unregister()
        stop(renderer)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--starts", type=int, default=30)
    ap.add_argument("--pixels", choices=("gl", "x11"), default="gl")
    ap.add_argument("--sizes", default=DEFAULT_SIZES, help="WIDTHxHEIGHT per camera, comma-separated")
    ap.add_argument("--rate", type=float, default=10.0)
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds for every camera's first image")
    ap.add_argument("--resizes", type=int, default=0,
                    help="then resize one more camera this many times (its CameraInfo alternating two sizes)")
    ap.add_argument("--resize-sizes", default="320x240,400x300", help="the two sizes of --resizes")
    ap.add_argument("--sim", action="store_true", help="run the simulator (camera_box world, RTF 0) beside")
    ap.add_argument("--prefix", default="",
                    help="command the renderer runs under (rosrun --prefix), e.g. valgrind")
    args = ap.parse_args()
    if args.starts <= 0:
        raise SystemExit("--starts must be > 0")
    sizes = parse_sizes(args.sizes)
    args.resize_sizes = parse_sizes(args.resize_sizes)
    if len(args.resize_sizes) != 2 or args.resizes < 0:
        raise SystemExit("--resize-sizes takes two sizes, --resizes a count >= 0")
    env = dict(os.environ)
    env["ROS_MASTER_URI"] = "http://127.0.0.1:%d" % free_port()
    env.pop("DISPLAY", None)        # the renderer starts its own Xvfb, as in the tests
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    logdir = scratch_dir("render_starts_")
    master = start(["roscore", "-p", env["ROS_MASTER_URI"].rsplit(":", 1)[1]], env,
                   os.path.join(logdir, "roscore.log"))
    tfs = []
    sim = None
    try:
        import rospy
        import rosgraph
        t0 = time.time()
        while not rosgraph.is_master_online():
            if time.time() - t0 > 30 or master.poll() is not None:
                raise SystemExit("roscore did not come up (log: %s)" % logdir)
            time.sleep(0.2)
        if args.sim:
            # beside the simulator running as fast as it can, as in render.sh: the renderer starts
            # on a busy CPU (the crashes seen so far were all in such runs)
            world = os.path.join(ROOT, "src/modrob_sim/test/fixtures/camera_box.world")
            sim = start(["roslaunch", "modrob_sim", "empty_world.launch", "gui:=false", "real_time_factor:=0",
                         "use_clock_frequency:=true", "pub_clock_frequency:=250", "world_name:=" + world],
                        env, os.path.join(logdir, "sim.log"))
        for i in range(len(sizes)):
            tfs.append(start(["rosrun", "tf2_ros", "static_transform_publisher",
                              "%g" % (i - 2), "-3", "1", "0", "0", "0", "world", "stress%d" % i,
                              "__name:=stress_tf%d" % i], env))
        rospy.init_node("render_starts", anonymous=True, disable_signals=True)
        failed = crashes = 0
        for k in range(args.starts):
            ok, secs, msg, ended = one_start(k, args, sizes, env, logdir)
            failed += not ok
            crashes += ended
            verdict = "ok" if ok else ("CRASHED" if ended else "FAILED")
            print("start %2d: %s (%.1f s)%s" % (k + 1, verdict, secs, "" if ok else ": " + msg), flush=True)
        print("pixels=%s, %d cameras (%s): %d of %d starts failed, %d of them crashed (logs: %s)"
              % (args.pixels, len(sizes), args.sizes, failed, args.starts, crashes, logdir), flush=True)
        return 1 if failed else 0
    finally:
        for p in tfs:
            stop(p)
        stop(sim)
        stop(master)


if __name__ == "__main__":
    sys.exit(main())

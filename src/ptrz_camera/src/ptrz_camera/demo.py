"""make demo SCENARIO=ptrz: the camera network tracks the ball for a while, headless.

Starts its own ROS master on a free port with tracking.launch (indoor world, N cameras, the
ball on its figure eight, the renderer), records the true and the estimated positions, and
writes under --out: ptrz_tracking.png (true vs estimated path, error over time), ptrz_<camera>.png
(the last frame of each camera), ptrz_tracking.csv, and prints one RESULT line. The truth is the
ball's link pose stamped on tf; the /gazebo/model_states poses must lie on it (ros/recorder.py)."""
import argparse
import csv
import os
import time

import cv2

from modrob_sim import scenario_launch


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="ptrz")
    ap.add_argument("--out", default="out")
    ap.add_argument("--cameras", type=int, default=3)
    ap.add_argument("--duration", type=float, default=60.0, help="simulated seconds recorded (default 60)")
    ap.add_argument("--real-time-factor", default="1", help="simulator pace (0 = as fast as possible)")
    ap.add_argument("--tolerance", type=float, default=0.05)
    ap.add_argument("--wall-timeout", type=float, default=900.0)
    ap.add_argument("--audit", action="store_true",
                    help="also write ptrz_audit.csv (every image against tf at its stamp) and "
                         "ptrz_network_log.txt (the sources of every fused estimate)")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    log = open(os.path.join(args.out, "ptrz_launch.log"), "w")
    # server_required: a simulator that dies (at start-up too) ends the launch, and the wait below
    cmd = ["ptrz_camera", "tracking.launch", "gui:=false",
           "server_required:=true", "cameras:=%d" % args.cameras,
           "real_time_factor:=%s" % args.real_time_factor]
    if args.audit:
        cmd.append("log:=%s" % os.path.abspath(os.path.join(args.out, "ptrz_network_log.txt")))
    print("[ptrz demo] roslaunch %s" % " ".join(cmd), flush=True)
    scenario_launch.sigterm_as_exit()
    launch = scenario_launch.start(cmd, log)
    try:
        return run(args, launch)
    finally:
        scenario_launch.stop(launch)
        log.close()


def stopped(args):
    """The RESULT line of a run whose launch ended (its simulator is required) before the recording did."""
    path = os.path.join(args.out, "ptrz_launch.log")
    with open(path) as f:
        fatal = [line.strip() for line in f if "[FATAL]" in line]
    if fatal:
        print("[ptrz demo] %s" % fatal[0], flush=True)
    print("RESULT %s: FAILURE -- the simulation stopped before the recording was complete (its messages: %s)"
          % (args.scenario, path), flush=True)
    return 1


def run(args, launch):
    import rospy
    from ptrz_camera.ros.recorder import TrackingRecorder
    from ptrz_camera.tracking import evaluate
    from ptrz_camera.worlds import FIELD
    names = ["ptrz"] if args.cameras == 1 else ["ptrz%d" % i for i in range(1, args.cameras + 1)]
    start_wall = time.monotonic()
    deadline = start_wall + args.wall_timeout
    import rosgraph
    master = rosgraph.Master("/ptrz_demo")
    while time.monotonic() < deadline:          # simulated time: /use_sim_time must be set first
        if launch.poll() is not None:
            return stopped(args)
        try:
            if master.getParam("/use_sim_time"):
                break
        except (IOError, rosgraph.MasterError):
            pass
        time.sleep(1.0)
    rospy.init_node("ptrz_demo", disable_signals=True)
    rec = TrackingRecorder(names)
    audit = None
    if args.audit:
        from ptrz_camera.ros.audit import ImageAudit
        audit = ImageAudit(names)
    print("[ptrz demo] waiting for the first network estimate ...", flush=True)
    while time.monotonic() < deadline and not rec.snapshot()[1]:
        if launch.poll() is not None:
            return stopped(args)
        time.sleep(0.5)
    if not rec.snapshot()[1]:
        print("RESULT %s: FAILURE -- no network estimate within %.0f wall s (see %s/ptrz_launch.log)"
              % (args.scenario, args.wall_timeout, args.out))
        return 1
    t0_sim, t0_wall = rospy.get_time(), time.monotonic()
    print("[ptrz demo] tracking from sim time %.1f s; recording %.0f s of simulated time"
          % (t0_sim, args.duration),
          flush=True)
    last_report = 0
    while time.monotonic() < deadline and rospy.get_time() - t0_sim < args.duration:
        if launch.poll() is not None:
            return stopped(args)
        time.sleep(0.5)
        if time.monotonic() - last_report > 15:
            last_report = time.monotonic()
            print("[ptrz demo] sim %.1f / %.0f s" % (rospy.get_time() - t0_sim, args.duration), flush=True)
    sim = rospy.get_time() - t0_sim
    rtf = sim / max(1e-6, time.monotonic() - t0_wall)
    truth, est, per_cam, pixels, images, states = rec.snapshot()
    truth = [p for p in truth if p[0] >= t0_sim]
    off = evaluate.off_path([p for p in states if p[0] >= t0_sim], truth)
    est = [p for p in est if p[0] >= t0_sim]
    pix = [p for ps in pixels.values() for p in ps]
    width, height = (images[names[0]].shape[1], images[names[0]].shape[0]) if images else (320, 128)
    s = evaluate.summarize(truth, est, args.tolerance, evaluate.centred_fraction(pix, width, height))
    field = (FIELD.centre_x - FIELD.length / 2, FIELD.centre_y - FIELD.width / 2, FIELD.length, FIELD.width)
    plot = os.path.join(args.out, "ptrz_tracking.png")
    evaluate.plot(plot, truth, est, per_cam, title="%d camera(s), %.0f s simulated" % (len(names), sim),
                  tolerance=args.tolerance, field=field)
    for name, img in images.items():
        cv2.imwrite(os.path.join(args.out, "ptrz_%s.png" % name), cv2.cvtColor(img, cv2.COLOR_RGB2BGR))
    with open(os.path.join(args.out, "ptrz_tracking.csv"), "w") as f:
        w = csv.writer(f)
        w.writerow(["kind", "t", "x", "y"])
        w.writerows([("true",) + tuple(p) for p in truth] + [("estimate",) + tuple(p) for p in est])
        w.writerows([("model_states",) + tuple(p) for p in states if p[0] >= t0_sim])
        w.writerows([(name,) + tuple(p) for name, pts in sorted(per_cam.items())
                     for p in pts if p[0] >= t0_sim])
    if audit is not None:
        path = os.path.join(args.out, "ptrz_audit.csv")
        rows = audit.rows(t0_sim - 5.0)
        with open(path, "w") as f:
            w = csv.writer(f)
            w.writerow(audit.COLUMNS)
            w.writerows(rows)
        print("[ptrz demo] audit of %d images with the ball: %s" % (len(rows), path), flush=True)
    t_end = t0_sim + sim
    cover = evaluate.coverage([p[0] for p in est], t0_sim, t_end)
    share = evaluate.published_share([p[0] for p in est], rec.detection_times(), t0_sim,
                                     max([p[0] for p in est] or [t0_sim]))
    ok = (s.n > 0 and s.max <= args.tolerance and sim >= 0.95 * args.duration
          and len(off) > 0 and off.max() < 0.01 and share >= 0.9 and s.centred >= 0.9)
    print("[ptrz demo] /gazebo/model_states: %d poses of the ball, at most %.1f mm from its stamped "
          "path (tf); longest gap between two stamped poses %.3f s"
          % (len(off), 1000 * (off.max() if len(off) else float("nan")),
             max([b[0] - a[0] for a, b in zip(truth, truth[1:])] or [0.0])), flush=True)
    frames = ", ".join("ptrz_%s.png" % n for n in sorted(images))
    print("[ptrz demo] wrote %s, %s" % (plot, frames), flush=True)
    values = (args.scenario, "SUCCESS" if ok else "FAILURE", len(names), sim, rtf, 100 * s.max,
              100 * s.within, 100 * args.tolerance, s.n, s.n / max(sim, 1e-6), 100 * share, 100 * cover,
              100 * s.mean, 100 * s.p95, 100 * s.centred)
    print("RESULT %s: %s -- %d camera(s), %.1f s simulated (real-time factor %.2f): max error %.1f cm, "
          "%.1f %% of the estimates within %.0f cm, %d estimates (%.1f per simulated s; for %.0f %% of the "
          "image times with a detection; one at most 0.5 s old during %.0f %% of the time), error mean "
          "%.1f cm, 95 %% %.1f cm, ball in the central third of the image in %.0f %% of detections"
          % values, flush=True)
    return 0 if ok else 1

#!/usr/bin/env python3
"""Camera renderer benchmark: frames per second per stream (640x480 and 1280x720, 1 and 5 streams)
and the simulator's real-time factor with and without the streams, in one run; then one 640x480
stream with one default changed (RViz's 4x multisampling back on, pixels grabbed from the X server
instead of read from OpenGL, the renderer at the simulator's priority, no rasterizer threads), as
ratios to the default in the same run; for every window also the simulator's CPU share and its
simulated seconds per CPU second (whether it lost CPU or does more work per step).

The simulator runs modrob_sim's camera_box world as fast as it can (real_time_factor 0); the
renderer (a separate process, its own Xvfb) renders N cameras asking for `--rate` fps each.
  python3 scripts/bench/render.py [--seconds 10] [--rate 30] [--write docs/benchmarks.md]
--write replaces the "Camera renderer" section of that file (appends it when there is none).
"""
import argparse
import os
import random
import subprocess
import sys
import threading
import time

from procs import cpu_seconds, start, stop

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CONFIGS = [(640, 480, 1), (640, 480, 5), (1280, 720, 1), (1280, 720, 5)]
# (label, renderer parameters) at 640x480, one stream
VARIANTS = [("RViz's 4x multisampling on", ["_antialiasing:=true"]),
            ("pixels grabbed from the X server", ["_pixels:=x11"]),
            ("renderer at the simulator's priority (`_nice:=0`)", ["_nice:=0"]),
            ("no llvmpipe rasterizer threads (`_render_threads:=0`)", ["_render_threads:=0"])]
HEADING = "## Camera renderer (RViz/OGRE off-screen)"
LOGS = os.path.join(ROOT, "out", "bench", "render")
FRAME = "gazebo/camera_post/camera_link/camera1"


class Meter(object):
    def __init__(self):
        import rospy
        from rosgraph_msgs.msg import Clock
        self.rospy = rospy
        self.lock = threading.Lock()
        self.clock = None
        self.counts = {}
        self.sim_pid = None
        self.cpu = (float("nan"), float("nan"))
        rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=1)

    def _on_clock(self, msg):
        with self.lock:
            self.clock = msg.clock.to_sec()

    def watch(self, topics):
        from sensor_msgs.msg import Image
        subs = []
        for t in topics:
            self.counts[t] = 0
            subs.append(self.rospy.Subscriber(t, Image, self._on_image, t, queue_size=2, buff_size=2 ** 25))
        return subs

    def _on_image(self, _msg, topic):
        with self.lock:
            self.counts[topic] += 1

    def measure(self, seconds, topics=()):
        """(real-time factor, [fps per topic]); ``self.cpu`` gets (CPU seconds of the simulator per
        wall second, simulated seconds per CPU second of it) for the same window."""
        with self.lock:
            c0, n0, w0 = self.clock, {t: self.counts[t] for t in topics}, time.monotonic()
        cpu0 = cpu_seconds(self.sim_pid) if self.sim_pid else None
        time.sleep(seconds)
        with self.lock:
            c1, n1, w1 = self.clock, {t: self.counts[t] for t in topics}, time.monotonic()
        cpu1 = cpu_seconds(self.sim_pid) if self.sim_pid else None
        rtf = (c1 - c0) / (w1 - w0) if c0 is not None and c1 is not None else float("nan")
        fps = [(n1[t] - n0[t]) / (w1 - w0) for t in topics]
        share = (cpu1 - cpu0) / (w1 - w0) if cpu0 is not None else float("nan")
        self.cpu = (share, rtf / share if share > 0 else float("nan"))
        return rtf, fps


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--rate", type=float, default=30.0)
    ap.add_argument("--write", default="", help="append the table to this markdown file")
    args = ap.parse_args()
    os.makedirs(LOGS, exist_ok=True)
    port = random.randint(20000, 29999)
    env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % port)
    env.pop("DISPLAY", None)
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    core = start(["roscore", "-p", str(port)], env)
    sim = renderer = None
    rows, variants, retries = [], [], []
    try:
        import rospy
        import rosgraph
        end = time.monotonic() + 30
        while not rosgraph.is_master_online() and time.monotonic() < end:
            time.sleep(0.3)
        world = os.path.join(ROOT, "src/modrob_sim/test/fixtures/camera_box.world")
        # /clock at 250 Hz of wall time, as bulbs_and_slides.launch: at every step (1000+/s) the
        # renderer's two clients (rospy and RViz's roscpp) would spend the CPU on /clock alone
        # topics through roscpp (MODROB_SIM_ROSCPP=1) as in the other benchmarks and make demo: with
        # rospy's publishers every subscriber of /clock and /tf (the renderer adds two of each) costs
        # the simulator a Python thread wake-up per message
        sim = start(["roslaunch", "modrob_sim", "empty_world.launch", "gui:=false", "real_time_factor:=0",
                     "use_clock_frequency:=true", "pub_clock_frequency:=250", "world_name:=" + world],
                    dict(env, MODROB_SIM_ROSCPP="1"))
        rospy.init_node("render_bench", anonymous=True, disable_signals=True)
        meter = Meter()
        end = time.monotonic() + 120
        while meter.clock is None or meter.clock < 2.0:      # the simulator is up and stepping
            if time.monotonic() > end:
                raise RuntimeError("the simulator published no /clock within 120 s")
            time.sleep(0.5)
        meter.sim_pid = sim_pid()
        base_rtf, _ = meter.measure(args.seconds)
        base_cpu = meter.cpu
        print("[bench] simulator alone: real-time factor %.2f, %.2f CPU s/s, %.1f simulated s per CPU s"
              % ((base_rtf,) + base_cpu), flush=True)

        runs = [0]

        def run(w, h, n, extra=()):
            # topics new for every run: rospy may not deliver on a topic re-subscribed right after
            # its last subscriber was unregistered
            runs[0] += 1
            prefix = "/bench/r%d" % runs[0]
            log = os.path.join(LOGS, "renderer_%d.log" % runs[0])
            cam = "{name: b%d, frame: '%s', image: " + prefix + "/b%d/image, width: %d, height: %d, fx: %.1f}"
            cams = ",".join(cam % (i, FRAME, i, w, h, w / 2.0) for i in range(n))
            renderer = start(["rosrun", "modrob_viz", "camera_renderer", "__name:=bench_renderer",
                              "_rate:=%g" % args.rate, "_sensors_param:=", "_screen:=4096x2304",
                              "_cameras:=[%s]" % cams] + list(extra), env, log)
            topics = [prefix + "/b%d/image" % i for i in range(n)]
            subs = meter.watch(topics)
            try:
                end = time.monotonic() + 90
                while time.monotonic() < end and min(meter.counts[t] for t in topics) < 3:
                    time.sleep(0.5)
                rtf, fps = meter.measure(args.seconds, topics)
            finally:
                for sub in subs:
                    sub.unregister()
                stop(renderer)
            time.sleep(3.0)
            if min(fps) == 0:
                print("[bench] no frames from a stream: see %s" % log, flush=True)
            return rtf, fps

        def run_retry(w, h, n, extra=()):
            """A renderer that gave a stream no frame at all is run once more (noted in the table)."""
            rtf, fps = run(w, h, n, extra)
            if min(fps) > 0:
                return rtf, fps, ""
            retries.append("%dx%d x%d %s" % (w, h, n, " ".join(extra)))
            rtf, fps = run(w, h, n, extra)
            return rtf, fps, " (2nd try)"

        def run_cpu(*a):
            rtf, fps, note = run_retry(*a)
            return rtf, fps, note, meter.cpu

        for w, h, n in CONFIGS:
            rtf, fps, note, cpu = run_cpu(w, h, n)
            rows.append((w, h, n, sum(fps) / len(fps), min(fps), rtf, note, cpu))
            print("[bench] %dx%d x%d: %.1f fps per stream (min %.1f), simulator RTF %.2f (alone %.2f)"
                  % (w, h, n, rows[-1][3], rows[-1][4], rtf, base_rtf), flush=True)
        for label, extra in VARIANTS:
            rtf, fps, note, cpu = run_cpu(640, 480, 1, extra)
            variants.append((label + note, fps[0], rtf, cpu))
            print("[bench] 640x480 x1, %s: %.1f fps, simulator RTF %.2f" % (label, fps[0], rtf), flush=True)
        after_rtf, _ = meter.measure(args.seconds)
        after_cpu = meter.cpu
    finally:
        stop(renderer)
        stop(sim)
        stop(core)
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], stdout=subprocess.PIPE,
                            text=True).stdout.strip()
    lines = ["", "## Camera renderer (RViz/OGRE off-screen)", "",
             "Command: `bash scripts/bench/render.sh` (%g s windows, cameras asking %g fps, simulator at "
             "real_time_factor 0 on modrob_sim's camera_box world, /clock at 250 Hz). Measured %s, "
             "commit %s, %s; load average %s."
             % (args.seconds, args.rate, time.strftime("%Y-%m-%d"), commit, "2 cores, Mesa llvmpipe, no GPU",
                open("/proc/loadavg").read().split()[0]),
             "", "Simulator CPU: its process's CPU seconds per wall second (its share of the 2 cores) and "
             "simulated seconds per CPU second of it (its efficiency: work it does per step). Alone: "
             "%.2f CPU s/s, %.1f simulated s per CPU s before the streams, %.2f / %.1f after."
             % (base_cpu + after_cpu),
             "", "| image | streams | fps per stream (mean) | slowest stream | simulator RTF with streams "
             "| RTF alone (before / after) | simulator CPU s/s | simulated s per CPU s |",
             "|---|---|---|---|---|---|---|---|"]
    for w, h, n, mean, low, rtf, note, cpu in rows:
        lines.append("| %dx%d%s | %d | %.1f | %.1f | %.2f (%+.0f %%) | %.2f / %.2f | %.2f | %.1f (%+.0f %%) |"
                     % (w, h, note, n, mean, low, rtf, 100.0 * (rtf / base_rtf - 1.0), base_rtf, after_rtf,
                        cpu[0], cpu[1], 100.0 * (cpu[1] / base_cpu[1] - 1.0)))
    default = rows[0][3] if rows else float("nan")
    first = " | ".join(["%.2f" % rows[0][5], "%.2f" % rows[0][7][0], "%.1f" % rows[0][7][1]]) if rows \
        else "- | - | -"
    lines += ["", "One 640x480 stream with a default changed, same run (fps relative to the default row "
              "above, %.1f fps):" % default, "",
              "| renderer | fps | vs default | simulator RTF | simulator CPU s/s | simulated s per CPU s |",
              "|---|---|---|---|---|---|",
              "| default (no multisampling, pixels read from OpenGL, nice 10, llvmpipe threads) "
              "| %.1f | 1.00 | %s |" % (default, first)]
    for label, fps, rtf, cpu in variants:
        ratio = fps / default if default else float("nan")
        lines.append("| %s | %.1f | %.2f | %.2f | %.2f | %.1f |" % (label, fps, ratio, rtf, cpu[0], cpu[1]))
    if retries:
        lines += ["", "Run twice because a stream gave no frame in the first try: %s." % "; ".join(retries)]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.write:
        write_section(args.write, text)
    return 0


def sim_pid():
    """Process id of the /gazebo node (its slave API's getPid)."""
    import xmlrpc.client
    import rosgraph
    import rosnode
    uri = rosnode.get_api_uri(rosgraph.Master("/render_bench"), "/gazebo")
    if not uri:
        raise RuntimeError("the master does not know the /gazebo node")
    return int(xmlrpc.client.ServerProxy(uri).getPid("/render_bench")[2])


def write_section(path, text):
    """Replace the camera renderer section of ``path`` (its heading up to the next '## ' heading)
    with ``text``, or append ``text`` when the file has no such section. Prose written under the
    table by hand is kept after the new table when it follows a line '<!-- render:notes -->'."""
    with open(path) as f:
        old = f.read()
    start = old.find(HEADING)
    if start < 0:
        new = old.rstrip("\n") + "\n" + text
    else:
        nxt = old.find("\n## ", start + len(HEADING))
        end = len(old) if nxt < 0 else nxt + 1
        section = old[start:end]
        notes = section.find("<!-- render:notes -->")
        keep = section[notes:] if notes >= 0 else ""
        body = text.lstrip("\n")
        new = old[:start] + body + ("\n" + keep.rstrip("\n") + "\n" if keep else "") \
            + ("\n" if end < len(old) else "") + old[end:]
    with open(path, "w") as f:
        f.write(new)


if __name__ == "__main__":
    sys.exit(main())

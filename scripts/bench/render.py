#!/usr/bin/env python3
"""Camera renderer benchmark: frames per second per stream (640x480 and 1280x720, 1 and 5 streams)
and the simulator's real-time factor beside the streams against the simulator alone, in one run;
then one 640x480 stream with one default changed (RViz's 4x multisampling back on, pixels grabbed
from the X server instead of read from OpenGL, the renderer at the simulator's priority, no
rasterizer threads, the renderer kept off the first CPU).

Alone and with-streams windows alternate (alone, renderer started, with streams, renderer
stopped, alone, ...; ``--repeats`` pairs per row), so that the load of other work on the machine
hits both: each row gives the median of the pairs' ratios (with streams / alone just before) with
their min-max, for the real-time factor and for the simulator's simulated seconds per CPU second
of its own process (the work it does per step, whatever CPU share it got), beside the CPU
seconds per wall second of the simulator and of the renderer (its process, Xvfb included).

The simulator runs modrob_sim's camera_box world as fast as it can (real_time_factor 0); the
renderer (a separate process, its own Xvfb) renders N cameras asking for `--rate` fps each.
  python3 scripts/bench/render.py [--seconds 8] [--rate 30] [--repeats 3] [--variant-repeats 1]
                                  [--rows N] [--no-variants] [--write docs/benchmarks.md]
--write replaces the "Camera renderer" section of that file (appends it when there is none).
"""
import argparse
import os
import random
import statistics
import subprocess
import sys
import threading
import time

from procs import cpu_seconds, descendants, start, stop

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CONFIGS = [(640, 480, 1), (640, 480, 5), (1280, 720, 1), (1280, 720, 5)]
DEFAULT = "default (no multisampling, pixels read from OpenGL, nice 10, every CPU, Mesa's threads)"
# (label, renderer parameters) at 640x480, one stream
VARIANTS = [("RViz's 4x multisampling on", ["_antialiasing:=true"]),
            ("pixels grabbed from the X server", ["_pixels:=x11"]),
            ("renderer at the simulator's priority (`_nice:=0`)", ["_nice:=0"]),
            ("no llvmpipe rasterizer threads (`_render_threads:=0`)", ["_render_threads:=0"]),
            ("renderer on every CPU but the first, one llvmpipe thread (`_cpus:=auto`)", ["_cpus:=auto"])]
HEADING = "## Camera renderer (RViz/OGRE off-screen)"
LOGS = os.path.join(ROOT, "out", "bench", "render")
FRAME = "gazebo/camera_post/camera_link/camera1"


def tree(pid):
    """``pid`` and its descendants (a snapshot from /proc), the Xvfb servers they started included
    (those run in sessions of their own but are still their children)."""
    return [pid] + descendants(pid)


def tree_cpu(pids):
    total = 0.0
    for p in pids:
        try:
            total += cpu_seconds(p)
        except (OSError, IndexError, ValueError):      # ended meanwhile
            continue
    return total


class Meter(object):
    def __init__(self):
        import rospy
        from rosgraph_msgs.msg import Clock
        self.rospy = rospy
        self.lock = threading.Lock()
        self.clock = None
        self.counts = {}
        self.sim_pid = None
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

    def measure(self, seconds, topics=(), renderer=None):
        """One window: {rtf, fps [per topic], sim_cpu (CPU s of the simulator per wall s), sim_eff
        (simulated s per CPU s of it), render_cpu (CPU s per wall s of ``renderer``'s process tree)}."""
        pids = tree(renderer.pid) if renderer is not None else []
        with self.lock:
            c0, n0, w0 = self.clock, {t: self.counts[t] for t in topics}, time.monotonic()
        cpu0, r0 = cpu_seconds(self.sim_pid), tree_cpu(pids)
        time.sleep(seconds)
        with self.lock:
            c1, n1, w1 = self.clock, {t: self.counts[t] for t in topics}, time.monotonic()
        cpu1, r1 = cpu_seconds(self.sim_pid), tree_cpu(pids)
        wall = w1 - w0
        rtf = (c1 - c0) / wall if c0 is not None and c1 is not None else float("nan")
        share = (cpu1 - cpu0) / wall
        return dict(rtf=rtf, fps=[(n1[t] - n0[t]) / wall for t in topics], sim_cpu=share,
                    sim_eff=rtf / share if share > 0 else float("nan"),
                    render_cpu=(r1 - r0) / wall if pids else 0.0)


def med(values):
    """(median, min, max) of the finite values (nan when none)."""
    v = [x for x in values if x == x]
    return (statistics.median(v), min(v), max(v)) if v else (float("nan"),) * 3


def fmt_ratio(values):
    """'-12 % (-20..-5)' for ratios 0.88 (0.80..0.95)."""
    m, lo, hi = med(values)
    if len(values) == 1:
        return "%+.0f %%" % (100 * (m - 1))
    return "%+.0f %% (%+.0f..%+.0f)" % (100 * (m - 1), 100 * (lo - 1), 100 * (hi - 1))


def fmt_range(values, spec="%.1f"):
    m, lo, hi = med(values)
    if len(values) == 1:
        return spec % m
    return (spec + " (" + spec + "-" + spec + ")") % (m, lo, hi)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=8.0, help="length of each window (s)")
    ap.add_argument("--rate", type=float, default=30.0, help="frames per second each camera asks")
    ap.add_argument("--repeats", type=int, default=3, help="alone / with-streams pairs per stream row")
    ap.add_argument("--variant-repeats", type=int, default=1, help="pairs per changed-default row")
    ap.add_argument("--rows", type=int, default=len(CONFIGS), help="only the first N stream rows")
    ap.add_argument("--no-variants", action="store_true", help="no changed-default rows")
    ap.add_argument("--write", default="", help="replace the section in this markdown file")
    args = ap.parse_args()
    if args.repeats < 1 or args.variant_repeats < 1 or args.seconds <= 0 or args.rate <= 0 or args.rows < 1:
        ap.error("--repeats, --variant-repeats and --rows must be >= 1, --seconds and --rate > 0")
    if args.write and (args.rows < len(CONFIGS) or args.no_variants):
        ap.error("--write records the whole benchmark: no --rows or --no-variants with it")
    os.makedirs(LOGS, exist_ok=True)
    port = random.randint(20000, 29999)
    env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % port)
    env.pop("DISPLAY", None)
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    core = start(["roscore", "-p", str(port)], env)
    sim = None
    rows, variants, retries, loads = [], [], [], []
    t_start = time.monotonic()
    try:
        import rospy
        import rosgraph
        end = time.monotonic() + 30
        while not rosgraph.is_master_online() and time.monotonic() < end:
            time.sleep(0.3)
        world = os.path.join(ROOT, "src/modrob_sim/test/fixtures/camera_box.world")
        # /clock at 250 Hz of wall time, as bulbs_and_slides.launch: at every step (1000+/s) the
        # renderer's two clients (rospy and RViz's roscpp) would spend the CPU on /clock alone;
        # topics through roscpp (the node's default)
        sim = start(["roslaunch", "modrob_sim", "empty_world.launch", "gui:=false", "real_time_factor:=0",
                     "use_clock_frequency:=true", "pub_clock_frequency:=250", "world_name:=" + world], env)
        rospy.init_node("render_bench", anonymous=True, disable_signals=True)
        meter = Meter()
        end = time.monotonic() + 120
        while meter.clock is None or meter.clock < 2.0:      # the simulator is up and stepping
            if time.monotonic() > end:
                raise RuntimeError("the simulator published no /clock within 120 s")
            time.sleep(0.5)
        meter.sim_pid = sim_pid()
        runs = [0]

        def with_streams(w, h, n, extra):
            """One window beside a renderer of ``n`` cameras started for it (stopped after)."""
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
                win = meter.measure(args.seconds, topics, renderer)
            finally:
                for sub in subs:
                    sub.unregister()
                stop(renderer)
            if min(win["fps"]) == 0:
                print("[bench] no frames from a stream: see %s" % log, flush=True)
            return win

        def pair(w, h, n, extra):
            """(alone window, with-streams window); a renderer that gave a stream no frame at all is
            run once more (noted in the table)."""
            time.sleep(2.0)                     # the last renderer's exit settles
            alone = meter.measure(args.seconds)
            loads.append(float(open("/proc/loadavg").read().split()[0]))
            win = with_streams(w, h, n, extra)
            if min(win["fps"]) == 0:
                retries.append("%dx%d x%d %s" % (w, h, n, " ".join(extra)))
                win = with_streams(w, h, n, extra)
            return alone, win

        def row(w, h, n, extra, repeats, label):
            pairs = []
            for k in range(repeats):
                alone, win = pair(w, h, n, extra)
                pairs.append((alone, win))
                print("[bench] %s %d/%d: %.1f fps per stream (min %.1f); simulator RTF %.1f alone, %.1f with "
                      "(%+.0f %%), simulated s per CPU s %.1f / %.1f (%+.0f %%), CPU s/s %.2f / %.2f, "
                      "renderer %.2f CPU s/s; load %.1f"
                      % (label, k + 1, repeats, sum(win["fps"]) / len(win["fps"]), min(win["fps"]),
                         alone["rtf"], win["rtf"], 100 * (win["rtf"] / alone["rtf"] - 1), alone["sim_eff"],
                         win["sim_eff"], 100 * (win["sim_eff"] / alone["sim_eff"] - 1), alone["sim_cpu"],
                         win["sim_cpu"], win["render_cpu"], loads[-1]), flush=True)
            return pairs

        for w, h, n in CONFIGS[:args.rows]:
            rows.append(((w, h, n), row(w, h, n, (), args.repeats, "%dx%d x%d" % (w, h, n))))
        for label, extra in ([] if args.no_variants else VARIANTS):
            variants.append((label, row(640, 480, 1, extra, args.variant_repeats, "640x480 x1, " + label)))
    finally:
        stop(sim)
        stop(core)
    minutes = (time.monotonic() - t_start) / 60.0
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], stdout=subprocess.PIPE,
                            text=True).stdout.strip()
    text = table(args, rows, variants, retries, loads, commit, minutes)
    print(text)
    if args.write:
        write_section(args.write, text)
    return 0


def summary(pairs):
    """Figures of one row from its (alone, with) window pairs."""
    fps = [sum(b["fps"]) / len(b["fps"]) for _a, b in pairs]
    return dict(fps=fps, low=[min(b["fps"]) for _a, b in pairs],
                rtf_ratio=[b["rtf"] / a["rtf"] for a, b in pairs],
                eff_ratio=[b["sim_eff"] / a["sim_eff"] for a, b in pairs],
                rtf_alone=[a["rtf"] for a, _b in pairs], rtf_with=[b["rtf"] for _a, b in pairs],
                cpu_alone=[a["sim_cpu"] for a, _b in pairs], cpu_with=[b["sim_cpu"] for _a, b in pairs],
                render_cpu=[b["render_cpu"] for _a, b in pairs])


def table(args, rows, variants, retries, loads, commit, minutes):
    lo, hi = (min(loads), max(loads)) if loads else (float("nan"), float("nan"))
    lines = ["", HEADING, "",
             "Command: `bash scripts/bench/render.sh --repeats %d --variant-repeats %d --seconds %g` "
             "(cameras asking %g fps, simulator at real_time_factor 0 on modrob_sim's camera_box world, "
             "/clock at 250 Hz). Windows alternate: the simulator alone, then beside a renderer started "
             "for the row's streams, which is stopped before the next alone window; each figure is the "
             "median over a row's pairs with (min-max), each ratio one with-streams window against the "
             "alone window just before it. Measured %s, commit %s, 2 cores, Mesa llvmpipe, no GPU, %.0f "
             "minutes; load average %.1f-%.1f during the run."
             % (args.repeats, args.variant_repeats, args.seconds, args.rate, time.strftime("%Y-%m-%d"),
                commit, minutes, lo, hi),
             "",
             "RTF: the simulator's real-time factor, with streams against alone. Simulated s per CPU s: "
             "simulated seconds per CPU second of the simulator's own process (the work it does per step, "
             "whatever share of the CPU it got), with streams against alone. CPU s/s: CPU seconds per wall "
             "second of the simulator (alone / with streams) and of the renderer (its process and Xvfb).",
             "",
             "| image | streams | pairs | fps per stream | slowest stream | simulator RTF alone -> with "
             "| RTF with / alone | simulated s per CPU s, with / alone | simulator CPU s/s alone / with "
             "| renderer CPU s/s |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for (w, h, n), pairs in rows:
        s = summary(pairs)
        lines.append("| %dx%d | %d | %d | %s | %s | %s -> %s | %s | %s | %s / %s | %s |"
                     % (w, h, n, len(pairs), fmt_range(s["fps"]), fmt_range(s["low"]),
                        fmt_range(s["rtf_alone"], "%.0f"), fmt_range(s["rtf_with"], "%.0f"),
                        fmt_ratio(s["rtf_ratio"]), fmt_ratio(s["eff_ratio"]),
                        fmt_range(s["cpu_alone"], "%.2f"), fmt_range(s["cpu_with"], "%.2f"),
                        fmt_range(s["render_cpu"], "%.2f")))
    default = summary(rows[0][1]) if rows else None
    base = med(default["fps"])[0] if default else float("nan")
    lines += ["", "One 640x480 stream with a default changed, same run (fps against the first row's median, "
              "%.1f fps):" % base, "",
              "| renderer | pairs | fps | vs default | RTF with / alone "
              "| simulated s per CPU s, with / alone | simulator CPU s/s alone / with | renderer CPU s/s |",
              "|---|---|---|---|---|---|---|---|"]

    def variant_row(label, pairs, vs):
        s = summary(pairs)
        return "| %s | %d | %s | %s | %s | %s | %s / %s | %s |" % (
            label, len(pairs), fmt_range(s["fps"]), vs, fmt_ratio(s["rtf_ratio"]),
            fmt_ratio(s["eff_ratio"]), fmt_range(s["cpu_alone"], "%.2f"), fmt_range(s["cpu_with"], "%.2f"),
            fmt_range(s["render_cpu"], "%.2f"))

    if default:
        lines.append(variant_row(DEFAULT, rows[0][1], "1.00"))
    for label, pairs in variants:
        ratio = med(summary(pairs)["fps"])[0] / base if base else float("nan")
        lines.append(variant_row(label, pairs, "%.2f" % ratio))
    if retries:
        lines += ["", "Run twice because a stream gave no frame in the first try: %s." % "; ".join(retries)]
    return "\n".join(lines) + "\n"


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

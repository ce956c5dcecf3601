#!/usr/bin/env python3
"""Where a camera_renderer frame's time goes: one camera rendered in this process (RViz/OGRE on a
private Xvfb, as the node does) for a few seconds, every step timed.

Steps per frame (wall ms, in the Qt thread): the placeholder round trip (publish, RViz takes it,
updates and renders: waiting in Qt's loop), the grab (X GetImage of the panel, QImage conversion,
numpy copy), the publish (format conversion, message, rospy's serialisation), our bookkeeping
(tf lookup, RViz status). CPU seconds per thread group (main = Qt/RViz/Python, llvmpipe = Mesa's
rasterizer threads, ROS = rospy/roscpp I/O threads) from /proc, for the same run.
  python3 scripts/bench/render_profile.py [--size 640x480] [--rate 60] [--seconds 10] [--rtf 0]
"""
import argparse
import collections
import os
import random
import sys
import time

from procs import start, stop

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FRAME = "gazebo/camera_post/camera_link/camera1"
TICK = os.sysconf("SC_CLK_TCK")


def thread_cpu():
    """{thread name: CPU seconds} of this process (threads of one name summed)."""
    out = collections.Counter()
    base = "/proc/self/task"
    for tid in os.listdir(base):
        try:
            with open(os.path.join(base, tid, "stat")) as f:
                stat = f.read()
        except OSError:
            continue
        name = stat[stat.index("(") + 1:stat.rindex(")")]
        fields = stat[stat.rindex(")") + 2:].split()
        cpu = (int(fields[11]) + int(fields[12])) / float(TICK)
        group = "main" if tid == str(os.getpid()) else \
            ("llvmpipe" if name.startswith("llvmpipe") else "ROS/other")
        out[group] += cpu
    return out


class Timer(object):
    def __init__(self):
        self.total = collections.Counter()
        self.count = collections.Counter()

    def wrap(self, obj, attr, label):
        fn = getattr(obj, attr)

        def timed(*a, **k):
            t0 = time.perf_counter()
            try:
                return fn(*a, **k)
            finally:
                self.total[label] += time.perf_counter() - t0
                self.count[label] += 1
        setattr(obj, attr, timed)


def profile(args):
    import numpy as np
    import rospy
    from python_qt_binding.QtCore import QTimer
    from sensor_msgs.msg import Image
    from modrob_viz.render import camera_spec
    from modrob_viz.render.node import CameraRendererNode
    from modrob_viz.render.rviz_renderer import RvizScene
    from modrob_viz.render.xvfb import ensure_display

    w, h = (int(v) for v in args.size.split("x"))
    xvfb = ensure_display(w + 200, h + 200)
    try:
        rospy.init_node("render_profile", disable_signals=True)
        spec = camera_spec.parse({"name": "p", "frame": FRAME, "image": "/profile/image", "width": w,
                                  "height": h, "fx": w / 2.0, "rate": args.rate}, args.rate)
        config = os.path.join(ROOT, "src/modrob_viz/config/camera_scene.rviz")
        scene = RvizScene(config, frame_rate=2.0 * args.rate, max_cameras=1, antialiasing=args.antialiasing,
                          pixels=args.pixels)
        node = CameraRendererNode(scene, [spec], args.rate, sensors_param="")
        timer = Timer()
        received = [0]
        rospy.Subscriber("/profile/image", Image, lambda _m: received.__setitem__(0, received[0] + 1),
                         queue_size=2, buff_size=2 ** 24)
        timer.wrap(scene, "grab", "grab (X GetImage + QImage + numpy)")
        timer.wrap(node, "_publish", "publish (convert + Image + rospy)")
        timer.wrap(node, "_tick", "our tick (all Python in the Qt thread)")
        timer.wrap(scene, "images_received", "RViz status read")
        timer.wrap(node.tf_buffer, "lookup_transform", "tf lookup")
        node.timer.timeout.disconnect()
        node.timer.timeout.connect(node._tick)       # the wrapped tick
        frames0 = [None]
        t0 = [None]
        cpu0 = [None]

        def begin():
            received[0] = 0
            frames0[0] = node.cams[spec["id"]].frames
            t0[0] = time.perf_counter()
            cpu0[0] = thread_cpu()
            for c in (timer.total, timer.count):
                c.clear()

        def end():
            scene.app.quit()
        QTimer.singleShot(int(args.warmup * 1000), begin)
        QTimer.singleShot(int((args.warmup + args.seconds) * 1000), end)
        scene.app.exec_()
        wall = time.perf_counter() - t0[0]
        cpu1 = thread_cpu()
        frames = node.cams[spec["id"]].frames - frames0[0]
        node.timer.stop()
        rgb = node.cams[spec["id"]].last_rgb
        seen = None if rgb is None else float(np.mean((rgb[..., 0] > 150) & (rgb[..., 1] < 80)))
        detail = grab_detail(scene, spec["id"], w, h)
    finally:
        if xvfb is not None:
            xvfb.stop()
    return wall, frames, timer, cpu0[0], cpu1, seen, detail, received[0]


def grab_detail(scene, cid, w, h, n=30):
    """ms per call of each step of RvizScene.grab, repeated on the last frame."""
    import numpy as np
    from python_qt_binding.QtCore import QPoint
    panel = scene.cameras[cid]["panel"]
    out = collections.Counter()
    for _ in range(n):
        t0 = time.perf_counter()
        pos = panel.mapToGlobal(QPoint(0, 0))
        pix = scene.app.primaryScreen().grabWindow(0, pos.x(), pos.y(), w, h)
        t1 = time.perf_counter()
        img = pix.toImage().convertToFormat(4)
        t2 = time.perf_counter()
        ptr = img.constBits()
        ptr.setsize(img.byteCount())
        arr = np.frombuffer(ptr, np.uint8).reshape(h, img.bytesPerLine() // 4, 4)
        rgb = np.ascontiguousarray(arr[:, :w, 2::-1])
        t3 = time.perf_counter()
        rgb.tobytes()
        t4 = time.perf_counter()
        out["X GetImage into a QPixmap (grabWindow)"] += t1 - t0
        out["QPixmap -> QImage RGB32"] += t2 - t1
        out["numpy BGRA -> RGB copy"] += t3 - t2
        out["bytes for the Image message"] += t4 - t3
    return {k: 1000 * v / n for k, v in out.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", default="640x480")
    ap.add_argument("--rate", type=float, default=60.0, help="fps asked (as fast as it goes: 60)")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--warmup", type=float, default=8.0)
    ap.add_argument("--rtf", default="0", help="simulator real_time_factor (0 = as fast as possible)")
    ap.add_argument("--antialiasing", action="store_true", help="RViz's 4x multisampling on")
    ap.add_argument("--pixels", default="gl", choices=("gl", "x11"), help="where the pixels are read")
    args = ap.parse_args()
    port = random.randint(20000, 29999)
    os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % port
    os.environ.pop("DISPLAY", None)
    env = dict(os.environ)
    core = start(["roscore", "-p", str(port)], env)
    sim = None
    try:
        import rosgraph
        end = time.monotonic() + 30
        while not rosgraph.is_master_online() and time.monotonic() < end:
            time.sleep(0.3)
        world = os.path.join(ROOT, "src/modrob_sim/test/fixtures/camera_box.world")
        sim = start(["roslaunch", "modrob_sim", "empty_world.launch", "gui:=false",
                     "real_time_factor:=" + args.rtf, "use_clock_frequency:=true", "pub_clock_frequency:=250",
                     "world_name:=" + world], env)
        import rospy
        end = time.monotonic() + 120
        while time.monotonic() < end:
            try:
                if rospy.get_param("/gazebo/camera_sensors", None) is not None or time.monotonic() > end:
                    break
            except Exception:
                pass
            time.sleep(0.5)
        wall, frames, timer, cpu0, cpu1, seen, detail, received = profile(args)
    finally:
        stop(sim)
        stop(core)
    fps = frames / wall
    print("render_profile: %s, asking %g fps, simulator real_time_factor %s, multisampling %s, "
          "pixels from %s, load average %s"
          % (args.size, args.rate, args.rtf, "on" if args.antialiasing else "off", args.pixels,
             open("/proc/loadavg").read().split()[0]))
    print("  %d frames in %.1f s: %.1f fps (red box pixels in the last frame: %.1f %%)"
          % (frames, wall, fps, 100 * (seen or 0)))
    per = max(frames, 1)
    tick = timer.total["our tick (all Python in the Qt thread)"]
    print("  wall time per frame: %.1f ms" % (1000 * wall / per))
    rows = [(label, timer.total[label]) for label in sorted(timer.total, key=lambda k: -timer.total[k])]
    rows.append(("Qt loop outside our tick (RViz update, render, idle)", wall - tick))
    for label, total in rows:
        print("    %-52s %6.2f ms/frame (%5.1f %% of wall)" % (label, 1000 * total / per, 100 * total / wall))
    print("  grab, each step on its own (ms per call):")
    for label, ms in detail.items():
        print("    %-42s %6.2f" % (label, ms))
    print("  images received by a subscriber in this process: %.1f fps" % (received / wall))
    print("  CPU per thread group (s, share of one core):")
    for group in sorted(cpu1):
        d = cpu1[group] - cpu0.get(group, 0.0)
        print("    %-10s %6.2f s  %5.1f %%   %.2f ms/frame" % (group, d, 100 * d / wall, 1000 * d / per))
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Top and side views of the robots' grasp-centre paths over the layout (two-robot hand-over)."""
import os

import numpy as np

COLOURS = ("tab:orange", "tab:purple", "tab:green", "tab:brown")


def _slide_outline(slide):
    """Corners (x, y) of a slide's channel seen from above."""
    u = slide.uphill
    side = np.array([-u[1], u[0], 0.0])
    side /= np.linalg.norm(side)
    far = slide.tip + slide.length * u
    pts = [slide.tip + slide.half_width * side, far + slide.half_width * side,
           far - slide.half_width * side, slide.tip - slide.half_width * side]
    return np.array([p[:2] for p in pts + pts[:1]])


def plot_paths(path, layout, paths_by_robot, title="grasp-centre paths", closest=None):
    """paths_by_robot: {robot id: (t, ee Nx3)}; closest: (distance m, text) or None. Writes a PNG with
    a top view (x-y) and a side view (x-z) of the slides, the cradle, the bases and the paths."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (top, side) = plt.subplots(1, 2, figsize=(13, 5.5))
    for name, slide in sorted(layout.slides.items()):
        colour = "tab:red" if "red" in name else "tab:blue"
        o = _slide_outline(slide)
        top.fill(o[:, 0], o[:, 1], color=colour, alpha=0.25, label=name.replace("_", " "))
        far = slide.tip + slide.length * slide.uphill
        side.plot([slide.tip[0], far[0]], [slide.tip[2], far[2]], color=colour, lw=3, alpha=0.5)
    marks = [(layout.place_point, "x", "release point")]
    if getattr(layout, "cradle_point", None) is not None:
        marks.append((layout.cradle_point, "s", "cradle"))
    for p, m, label in marks:
        top.plot(p[0], p[1], "k" + m, ms=9, mfc="none", label=label)
        side.plot(p[0], p[2], "k" + m, ms=9, mfc="none")
    for i, (_, base) in enumerate(layout.robots):
        top.plot(base[0], base[1], "o", color=COLOURS[i % len(COLOURS)], ms=12)
        top.annotate("modrob%d base" % i, (base[0], base[1]), textcoords="offset points", xytext=(8, -4),
                     fontsize=8)
    for rid in sorted(paths_by_robot):
        _, ee = paths_by_robot[rid]
        if len(ee) == 0:
            continue
        c = COLOURS[rid % len(COLOURS)]
        top.plot(ee[:, 0], ee[:, 1], color=c, lw=1.5, label="modrob%d grasp centre" % rid)
        side.plot(ee[:, 0], ee[:, 2], color=c, lw=1.5)
    top.set_xlabel("x [m]")
    top.set_ylabel("y [m]")
    top.set_title("top view")
    top.set_aspect("equal", adjustable="datalim")
    top.grid(True, alpha=0.3)
    top.legend(loc="best", fontsize=7)
    side.set_xlabel("x [m]")
    side.set_ylabel("z [m]")
    side.set_title("side view (x-z)")
    side.grid(True, alpha=0.3)
    if closest is not None:
        top.text(0.01, 0.01, "arms' closest approach %.0f mm\n(%s)" % (1000 * closest[0], closest[1]),
                 transform=top.transAxes, fontsize=7, va="bottom")
    fig.suptitle(title)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path

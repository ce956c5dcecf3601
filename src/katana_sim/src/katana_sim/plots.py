"""PNG figures of the Katana scenario (matplotlib, Agg): joint tracking, and the scan with its
detections."""
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from katana_sim.kinematics import JOINTS  # noqa: E402


def plot_joint_tracking(log, path):
    """log: [(t, desired[5], actual[5])]; one panel per arm joint: set-point of the running move and
    the joint's angle."""
    fig, axes = plt.subplots(len(JOINTS), 1, figsize=(9, 10), sharex=True)
    if log:
        t0 = log[0][0]
        ts = [t - t0 for t, _, _ in log]
        for i, (ax, name) in enumerate(zip(axes, JOINTS)):
            ax.plot(ts, [d[i] for _, d, _ in log], "--", color="tab:orange",
                    label="commanded end point of the move (with the load offset)")
            ax.plot(ts, [a[i] for _, _, a in log], color="tab:blue", label="actual")
            ax.set_ylabel(name.replace("katana_", "").replace("_joint", "") + " (rad)", fontsize=8)
            ax.grid(alpha=0.3)
        axes[0].legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("simulated time (s)")
    fig.suptitle("Katana joint tracking during the can stack")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def plot_scan(angles, ranges, range_min, range_max, detections, path,
              title="laser scan and detected objects"):
    """Top view in the laser frame: beams in range (blue), out of range (grey, at range_max),
    detected centres (green crosses) with their radius circles."""
    fig, ax = plt.subplots(figsize=(7, 7))
    xin, yin, xout, yout = [], [], [], []
    for a, r in zip(angles, ranges):
        if range_min <= r <= range_max and math.isfinite(r):
            xin.append(r * math.cos(a))
            yin.append(r * math.sin(a))
        else:
            xout.append(range_max * math.cos(a))
            yout.append(range_max * math.sin(a))
    ax.plot(xout, yout, ".", color="0.8", markersize=2, label="no return")
    ax.plot(xin, yin, ".", color="tab:blue", markersize=4, label="in range")
    for i, d in enumerate(detections):
        ax.plot(d.x, d.y, "x", color="tab:green", markersize=10, mew=2,
                label="detected centre" if i == 0 else None)
        ax.add_patch(plt.Circle((d.x, d.y), d.radius, fill=False, color="tab:green"))
        ax.annotate("%d: (%.3f, %.3f)" % (i, d.x, d.y), (d.x, d.y), textcoords="offset points", xytext=(8, 8))
    ax.plot([0], [0], "s", color="k", label="laser")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m, laser forward)")
    ax.set_ylabel("y (m, laser left)")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path

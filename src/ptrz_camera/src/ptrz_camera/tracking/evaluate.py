"""How well the network located the ball: estimates against the true path (interpolated at each
estimate's time), how centred the ball stayed in the images, and a plot of both paths."""
from collections import namedtuple

import numpy as np

Summary = namedtuple("Summary", "n mean max p95 within duration centred")


def errors(truth, estimates):
    """Distances (m) of each estimate (t, x, y) to the truth (t, x, y) interpolated at its time;
    estimates outside the truth's time span are skipped. Returns (times, errors)."""
    if len(truth) < 2 or not len(estimates):
        return np.zeros(0), np.zeros(0)
    tr = np.asarray(truth, dtype=float)
    es = np.asarray(estimates, dtype=float)
    order = np.argsort(tr[:, 0])
    tr = tr[order]
    keep = (es[:, 0] >= tr[0, 0]) & (es[:, 0] <= tr[-1, 0])
    es = es[keep]
    x = np.interp(es[:, 0], tr[:, 0], tr[:, 1])
    y = np.interp(es[:, 0], tr[:, 0], tr[:, 2])
    return es[:, 0], np.hypot(es[:, 1] - x, es[:, 2] - y)


def off_path(points, path, window=1.0):
    """Distance (m) of each point (t, x, y) to the polyline of ``path`` (t, x, y) between the path
    samples within ``window`` s of the point's time (points of poorly known time, such as
    model_states kept with their time of arrival); points outside the path's time span skipped."""
    if len(path) < 2 or not len(points):
        return np.zeros(0)
    pa = np.asarray(sorted(path), dtype=float)
    out = []
    for t, x, y in points:
        if t < pa[0, 0] or t > pa[-1, 0]:
            continue
        i0 = max(0, int(np.searchsorted(pa[:, 0], t - window)) - 1)
        i1 = min(len(pa), int(np.searchsorted(pa[:, 0], t + window)) + 1)
        a, b = pa[i0:i1 - 1, 1:], pa[i0 + 1:i1, 1:]
        ab = b - a
        L2 = np.maximum((ab ** 2).sum(axis=1), 1e-18)
        s = np.clip(((np.array([x, y]) - a) * ab).sum(axis=1) / L2, 0.0, 1.0)
        out.append(float(np.min(np.hypot(*(a + s[:, None] * ab - (x, y)).T))))
    return np.asarray(out)


def centred_fraction(pixels, width, height):
    """Share of detections (u, v) inside the central third of the image (both axes)."""
    if not len(pixels):
        return 0.0
    p = np.asarray(pixels, dtype=float)
    inside = (np.abs(p[:, 0] - width / 2.0) <= width / 6.0) & (np.abs(p[:, 1] - height / 2.0) <= height / 6.0)
    return float(np.mean(inside))


def coverage(times, t0, t1, max_age=0.5):
    """Share of the simulated time [t0, t1] at which the newest published estimate (times) is at
    most ``max_age`` s old."""
    if t1 <= t0:
        return 0.0
    ts = np.clip(np.sort(np.asarray(times, dtype=float)), t0, t1)
    covered = 0.0
    for a, b in zip(ts, np.append(ts[1:], t1)):
        covered += min(b - a, max_age)
    return float(min(1.0, covered / (t1 - t0)))


def published_share(estimate_times, detection_times, t0, t1):
    """Share of the image times in [t0, t1] at which a camera detected the ball that gave a
    published estimate."""
    det = {round(t, 3) for t in detection_times if t0 <= t <= t1}
    if not det:
        return 0.0
    return len(det & {round(t, 3) for t in estimate_times}) / float(len(det))


def summarize(truth, estimates, tolerance=0.05, centred=0.0):
    t, e = errors(truth, estimates)
    if not len(e):
        return Summary(0, float("nan"), float("nan"), float("nan"), 0.0, 0.0, centred)
    return Summary(len(e), float(np.mean(e)), float(np.max(e)), float(np.percentile(e, 95)),
                   float(np.mean(e <= tolerance)), float(t[-1] - t[0]), centred)


def plot(path, truth, estimates, per_camera=None, title="", tolerance=0.05, field=None):
    """PNG: the true path and the estimates on the floor (left), the error over time (right)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle
    tr = np.asarray(truth, dtype=float)
    es = np.asarray(estimates, dtype=float) if len(estimates) else np.zeros((0, 3))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5), gridspec_kw={"width_ratios": [1.4, 1]})
    if field is not None:
        ax.add_patch(Rectangle((field[0], field[1]), field[2], field[3], fill=False, color="0.5", lw=1))
    if len(tr):
        ax.plot(tr[:, 1], tr[:, 2], "-", color="k", lw=1.5,
                label="true path (the ball's pose stamped on tf = /gazebo/model_states)")
    for name, pts in sorted((per_camera or {}).items()):
        p = np.asarray(pts, dtype=float)
        if len(p):
            ax.plot(p[:, 1], p[:, 2], ".", ms=2, alpha=0.5, label="%s alone" % name)
    if len(es):
        ax.plot(es[:, 1], es[:, 2], ".", color="tab:red", ms=3, label="network estimate (/ptrz_network/ball)")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(loc="upper right", fontsize=7)
    ax.set_title(title or "ball on the floor: true vs estimated")
    t, e = errors(truth, estimates)
    if len(e):
        bx.plot(t, e * 100.0, ".", ms=3, color="tab:red")
    bx.axhline(tolerance * 100.0, color="0.4", ls="--", label="%.0f cm" % (tolerance * 100))
    bx.set_xlabel("simulated time (s)")
    bx.set_ylabel("error (cm)")
    bx.legend(loc="upper right")
    bx.set_title("network estimate error")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)

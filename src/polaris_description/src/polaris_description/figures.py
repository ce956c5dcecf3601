"""Plots (matplotlib, Agg): speed over time and east/north path, one curve per run."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def speed_plot(runs, path, reference=None, title="Ground speed"):
    """``runs``: list of (label, samples). Samples need t and speed."""
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for label, samples in runs:
        ax.plot([s["t"] for s in samples], [s["speed"] for s in samples], label=label, lw=1.2)
    if reference is not None:
        ax.axhline(reference, color="k", ls="--", lw=0.8, label="r*omega = %.2f m/s" % reference)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("speed [m/s]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def path_plot(runs, path, title="Path (east/north)", extra=None):
    """``runs``: list of (label, samples) with x (east) and y (north). ``extra(ax)`` draws more."""
    fig, ax = plt.subplots(figsize=(7, 6))
    for label, samples in runs:
        ax.plot([s["x"] for s in samples], [s["y"] for s in samples], label=label, lw=1.2)
    if extra is not None:
        extra(ax)
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def grid_plots(runs, speed_path, path_path, reference):
    """Figure 7 and 8 analogues: one panel per run (label, samples, events)."""
    n = len(runs)
    cols = 3
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(12, 3.3 * rows), squeeze=False)
    for ax, (label, samples, events) in zip(axes.flat, runs):
        ax.plot([s["t"] for s in samples], [s["speed"] for s in samples], lw=1.2)
        ax.axhline(reference, color="k", ls="--", lw=0.8)
        for t, _ in events:
            ax.axvline(t, color="tab:red", ls=":", lw=0.8)
        ax.set_title(label, fontsize=9)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("speed [m/s]")
        ax.set_ylim(0.0, max(1.0, max(s["speed"] for s in samples) * 1.1))
        ax.grid(True, alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.suptitle("Ground speed, 2 rad/s on the rear wheels (dashed: r*omega = %.2f m/s; "
                 "dotted: steer 0.7 rad / straighten)" % reference, fontsize=10)
    fig.tight_layout()
    fig.savefig(speed_path, dpi=100)
    plt.close(fig)
    fig, axes = plt.subplots(rows, cols, figsize=(12, 3.6 * rows), squeeze=False)
    for ax, (label, samples, events) in zip(axes.flat, runs):
        ax.plot([s["x"] for s in samples], [s["y"] for s in samples], lw=1.4)
        ax.plot(samples[0]["x"], samples[0]["y"], "go", ms=4)
        ax.plot(samples[-1]["x"], samples[-1]["y"], "rs", ms=4)
        ax.set_title(label, fontsize=9)
        ax.set_xlabel("east [m]")
        ax.set_ylabel("north [m]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.suptitle("East/north path: straight, then 0.7 rad on both steering blocks until ~90 deg, "
                 "then straight (o start, square end)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path_path, dpi=100)
    plt.close(fig)

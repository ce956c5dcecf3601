"""Tuning results as ros_control YAML and as a before/after plot (PNG, matplotlib Agg)."""
import os

import yaml


def round_gains(g):
    out = {}
    for k in ("p", "i", "d", "i_clamp"):
        if k in g:
            out[k] = float("%.5g" % g[k])
    out["antiwindup"] = bool(g.get("antiwindup", True))
    return out


def controller_yaml(namespace, joint, gains, controller=None, comment=None):
    """ros_control YAML text for one effort_controllers/JointPositionController."""
    controller = controller or ("%s_position_controller" % joint)
    data = {namespace.strip("/"): {controller: {"type": "effort_controllers/JointPositionController",
                                                "joint": joint, "pid": round_gains(gains)}}}
    head = "".join("# %s\n" % line for line in (comment or "").splitlines())
    return head + yaml.safe_dump(data, default_flow_style=False, sort_keys=False)


def plot_step(path, title, traces):
    """traces: list of (label, Trace). One figure: position (and set-point) and effort over time."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    for i, (label, tr) in enumerate(traces):
        if i == 0:
            ax1.plot(tr.t, tr.setpoint, "k--", lw=1, label="command")
        ax1.plot(tr.t, tr.position, lw=1.5, label=label)
        ax2.plot(tr.t, tr.effort, lw=1, label=label)
    ax1.set_ylabel("joint position [rad or m]")
    ax1.set_title(title)
    ax1.grid(True, alpha=0.3)
    ax1.legend(loc="best", fontsize=8)
    ax2.set_ylabel("effort [N m or N]")
    ax2.set_xlabel("time [s]")
    ax2.grid(True, alpha=0.3)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path

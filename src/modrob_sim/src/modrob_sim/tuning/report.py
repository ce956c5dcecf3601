"""Tuning results as ros_control YAML and as a before/after plot (PNG, matplotlib Agg)."""
import os

import yaml

from modrob_sim.tuning import TuningError


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


def update_gains_table(path, robot_key, joint, gains, info):
    """Merge one joint's tuned gains into the shared table ``path`` (YAML):
    robots: {<order>: {<joint>: {p, i, d, i_clamp, antiwindup, method, ...}}}."""
    table = {}
    if os.path.exists(path):
        with open(path) as fh:
            try:
                table = yaml.safe_load(fh) or {}
            except yaml.YAMLError as exc:
                raise TuningError("%s is not valid YAML (%s): fix or remove it" % (path, exc))
    robots = table.setdefault("robots", {})
    entry = round_gains(gains)
    entry.update(info)
    robots.setdefault(robot_key, {})[joint] = entry
    header = ("# PID gains tuned by `rosrun modrob_sim tune_pid` (relay feedback + Ziegler-Nichols tables,\n"
              "# then the seed's sinusoid check), per module order and joint, in ros_control's pid keys.\n"
              "# create_urdf_and_gazebo (modrob_build) takes a robot's default gains from here. Regenerate\n"
              "# with `rosrun modrob_sim tune_pid --order ... --all --defaults`; do not edit by hand.\n")
    with open(path, "w") as fh:
        fh.write(header + yaml.safe_dump(table, default_flow_style=False, sort_keys=True))
    return table


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

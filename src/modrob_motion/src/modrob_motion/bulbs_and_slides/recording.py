"""What a run leaves behind: end-effector trajectory bag and commanded-vs-measured joint plot."""
import os

import numpy as np


class Recorder(object):
    """Samples every robot's commanded and measured arm joints and its end-effector position
    (forward kinematics of the measured joints) at most every ``period`` simulated seconds."""

    def __init__(self, fk_by_robot, period=0.02, clock=None):
        self.fk = fk_by_robot          # robot_id -> callable(q array) -> (x, y, z) world
        self.period = period
        self.clock = clock
        self.rows = {}                 # robot_id -> list of (t, cmd, meas, ee, finger_effort)
        self._last = {}

    def sample(self, arm):
        t = self.clock()
        rid = arm.info.robot_id
        if t - self._last.get(rid, -1e9) < self.period:
            return
        self._last[rid] = t
        names = arm.info.arm_joints
        meas = arm.measured(names)
        cmd = arm.commanded(names)
        ee = self.fk[rid](meas)
        fingers = arm.info.gripper.joints if arm.info.gripper else []
        eff = float(np.mean(np.abs(arm.efforts(fingers)))) if fingers else 0.0
        self.rows.setdefault(rid, []).append((t, cmd, meas, np.asarray(ee), eff))

    def arrays(self, rid):
        rows = self.rows.get(rid, [])
        if not rows:
            return None
        t = np.array([r[0] for r in rows])
        return t, np.array([r[1] for r in rows]), np.array([r[2] for r in rows]), \
            np.array([r[3] for r in rows]), np.array([r[4] for r in rows])

    def write_bag(self, path, frame="world"):
        """geometry_msgs/PointStamped on /modrob<N>/ee_trajectory (the seed's trajectory recorder's
        type for 3D points), stamped with simulated time."""
        import rosbag
        import rospy
        from geometry_msgs.msg import PointStamped
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        count = 0
        with rosbag.Bag(path, "w") as bag:
            for rid in sorted(self.rows):
                t, _, _, ee, _ = self.arrays(rid)
                for tk, p in zip(t, ee):
                    msg = PointStamped()
                    msg.header.stamp = rospy.Time.from_sec(max(tk, 1e-6))
                    msg.header.frame_id = frame
                    msg.point.x, msg.point.y, msg.point.z = (float(v) for v in p)
                    bag.write("/modrob%d/ee_trajectory" % rid, msg, msg.header.stamp)
                    count += 1
        return count

    def broken_at_gaps(self, t, *series, gap=None):
        """The samples with a row of NaN wherever ``gap`` (10 sampling periods, at least 0.5 s) or
        more of simulated time passed without one (the scenario samples only while a robot moves,
        settles or grips; not while it waits for a bulb or plans), so that a plot shows no line
        across time that was not recorded. Returns (t, *series, [(gap start, gap end), ...])."""
        gap = max(10 * self.period, 0.5) if gap is None else gap
        starts = np.nonzero(np.diff(t) >= gap)[0] if len(t) else np.array([], dtype=int)
        out_t = np.insert(np.asarray(t, dtype=float), starts + 1, np.nan)
        out = [np.insert(np.asarray(s, dtype=float), starts + 1, np.nan, axis=0) for s in series]
        return (out_t,) + tuple(out) + ([(t[i], t[i + 1]) for i in starts],)

    def plot_joints(self, path, joint_names_by_robot, title="commanded vs measured joint angles"):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        robots = sorted(self.rows)
        n = max(len(joint_names_by_robot[r]) for r in robots)
        fig, axes = plt.subplots(n, len(robots), figsize=(7 * len(robots), 1.7 * n + 1), squeeze=False,
                                 sharex="col")
        for c, rid in enumerate(robots):
            t, cmd, meas, _, _ = self.arrays(rid)
            err_all = np.abs(cmd - meas)
            t, cmd, meas, gaps = self.broken_at_gaps(t, cmd, meas)
            for j, name in enumerate(joint_names_by_robot[rid]):
                ax = axes[j][c]
                for k, (a, b) in enumerate(gaps):
                    ax.axvspan(a, b, color="0.9", lw=0, label="not recorded" if k == 0 else None)
                ax.plot(t, cmd[:, j], "k--", lw=1, label="commanded")
                ax.plot(t, meas[:, j], lw=1.3, label="measured")
                err = np.nanmax(err_all[:, j]) if len(err_all) else 0.0
                ax.set_ylabel("%s [rad]" % name, fontsize=8)
                ax.text(0.01, 0.85, "max |error| %.3f rad" % err, transform=ax.transAxes, fontsize=7)
                ax.grid(True, alpha=0.3)
                if j == 0:
                    ax.set_title("modrob%d" % rid)
                    ax.legend(loc="upper right", fontsize=7)
            axes[len(joint_names_by_robot[rid]) - 1][c].set_xlabel("simulated time [s]")
        fig.suptitle(title)
        fig.tight_layout()
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        fig.savefig(path, dpi=90)
        plt.close(fig)
        return path

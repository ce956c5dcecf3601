"""Distances over time for the control-device user tests: CSV and a PNG plot like the seed's
figure 17 (red: end effector to goal, turquoise: end effector to the trajectory). No rospy."""
import csv
import math
import os

from modrob_viz.errors import VizError


class DistanceLog(object):
    """Rows of (time [s], distance_to_endpoint [m], distance_to_trajectory [m] or NaN)."""

    def __init__(self):
        self.rows = []

    def add(self, t, d_end, d_traj=float("nan")):
        self.rows.append((float(t), float(d_end), float(d_traj)))

    def __len__(self):
        return len(self.rows)

    def write_csv(self, path):
        _folder(path)
        tmp = path + ".part"  # written aside and renamed: readers never see half a file
        with open(tmp, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["time_s", "distance_to_endpoint_m", "distance_to_trajectory_m"])
            for t, a, b in list(self.rows):  # a snapshot: a node may append meanwhile
                w.writerow(["%.4f" % t, "%.6f" % a, "" if math.isnan(b) else "%.6f" % b])
        os.replace(tmp, path)
        return path

    @staticmethod
    def read_csv(path):
        log = DistanceLog()
        with open(path) as f:
            for row in csv.DictReader(f):
                log.add(row["time_s"], row["distance_to_endpoint_m"],
                        row["distance_to_trajectory_m"] or "nan")
        return log

    def plot(self, path, title="Control device user test"):
        """A PNG of both distances over time (matplotlib's Agg canvas; no pyplot state, so a node
        may call it from a timer thread)."""
        from matplotlib.figure import Figure
        _folder(path)
        rows = list(self.rows)  # a snapshot: a node may append meanwhile
        t = [r[0] for r in rows]
        fig = Figure(figsize=(8, 4), dpi=100)
        ax = fig.add_subplot(1, 1, 1)
        ax.plot(t, [r[1] for r in rows], color="red", label="end effector to end point")
        if any(not math.isnan(r[2]) for r in rows):
            ax.plot(t, [r[2] for r in rows], color="turquoise", label="end effector to trajectory")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("distance [m]")
        ax.set_title(title)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right")
        fig.tight_layout()
        tmp = path + ".part.png"
        fig.savefig(tmp, format="png")
        os.replace(tmp, path)
        return path


def _folder(path):
    if not path:
        raise VizError("no output file given")
    folder = os.path.dirname(os.path.abspath(path))
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as err:
        raise VizError("cannot create folder '%s': %s" % (folder, err))

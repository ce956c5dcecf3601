"""Recorded series, pure (no rospy): samples (t, value) per series name, the rolling window the
plot shows, CSV and PNG on exit. Times are ROS time in seconds (simulated time under
use_sim_time); the plot's x axis is seconds since the first sample of any series."""
import csv
import os
import threading

from rqt_plot.errors import PlotError

MAX_SAMPLES = 1000000          # per series; the oldest go first beyond this


class SeriesStore(object):
    def __init__(self, names, max_samples=MAX_SAMPLES):
        self.names = list(names)
        self.max_samples = max_samples
        self.lock = threading.Lock()
        self.data = {n: [] for n in self.names}
        self.t0 = None

    def add_name(self, name):
        with self.lock:
            if name not in self.data:
                self.names.append(name)
                self.data[name] = []

    def remove_name(self, name):
        with self.lock:
            if name in self.data:
                self.names.remove(name)
                del self.data[name]

    def append(self, name, t, value):
        with self.lock:
            samples = self.data[name]
            samples.append((t, value))
            if len(samples) > self.max_samples:
                del samples[:len(samples) - self.max_samples]
            if self.t0 is None or t < self.t0:
                self.t0 = t

    def clear(self):
        with self.lock:
            for samples in self.data.values():
                del samples[:]
            self.t0 = None

    def trim(self, duration):
        """Drop samples later than ``duration`` s after the first one (--duration's exact span)."""
        with self.lock:
            if self.t0 is None:
                return
            t0 = self.t0
            # t - t0 <= duration, not t <= t0 + duration: the span a reader computes (last - first)
            # must not exceed the duration by a rounding error (3.05 + 5.0 = 8.05, but 8.05 - 3.05
            # = 5.000000000000001)
            for samples in self.data.values():
                samples[:] = [s for s in samples if s[0] - t0 <= duration]

    def latest_time(self):
        with self.lock:
            times = [s[-1][0] for s in self.data.values() if s]
        return max(times) if times else None

    def count(self):
        with self.lock:
            return sum(len(s) for s in self.data.values())

    def span(self):
        """Seconds between the first and the latest sample (0 when empty)."""
        latest = self.latest_time()
        return 0.0 if latest is None or self.t0 is None else latest - self.t0

    def window(self, width):
        """{name: (xs, ys)} of the last ``width`` seconds (all when width <= 0); xs relative to t0."""
        latest = self.latest_time()
        out = {}
        with self.lock:
            for name in self.names:
                samples = self.data[name]
                if latest is not None and width > 0:
                    lo = latest - width
                    samples = [s for s in samples[-50000:] if s[0] >= lo]
                out[name] = ([t - self.t0 for t, _ in samples] if samples else [],
                             [v for _, v in samples])
        return out

    def rows(self):
        """(time, series, value) for every sample, in time order (series order breaks ties)."""
        with self.lock:
            rows = [(t, i, n, v) for i, n in enumerate(self.names) for t, v in self.data[n]]
        rows.sort(key=lambda r: (r[0], r[1]))
        return [(t, n, v) for t, _, n, v in rows]


def write_csv(store, path):
    """Long format, one sample a row: ``time,series,value`` (time in ROS seconds, full precision)."""
    _folder(path)
    try:
        with open(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["time", "series", "value"])
            for t, n, v in store.rows():
                w.writerow(["%.9f" % t, n, repr(v)])
    except OSError as err:
        raise PlotError("cannot write %s: %s" % (path, err))
    return path


def read_csv(path):
    """{series: [(t, value)]} from a file write_csv wrote."""
    out = {}
    with open(path, newline="") as f:
        r = csv.reader(f)
        header = next(r, None)
        if header != ["time", "series", "value"]:
            raise PlotError("%s is not an rqt_plot CSV (header %s)" % (path, header))
        for t, n, v in r:
            out.setdefault(n, []).append((float(t), float(v)))
    return out


def draw(figure, store, width, title=""):
    """Draw the window of ``store`` into a matplotlib ``figure`` (cleared first)."""
    figure.clf()
    ax = figure.add_subplot(111)
    shown = store.window(width)
    for name in store.names:
        xs, ys = shown[name]
        ax.plot(xs, ys, label=name, linewidth=1.3)
    ax.set_xlabel("time [s] (ROS time since the first sample)")
    ax.grid(True, alpha=0.4)
    if store.names:
        ax.legend(loc="best", fontsize=8)
    if title:
        ax.set_title(title)
    latest = store.latest_time()
    if latest is not None and width > 0 and store.t0 is not None:
        right = latest - store.t0
        ax.set_xlim(max(0.0, right - width), max(right, width))
    figure.tight_layout()
    return ax


def write_png(store, path, width, title=""):
    from matplotlib.figure import Figure
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    _folder(path)
    fig = Figure(figsize=(9, 5), dpi=100)
    FigureCanvasAgg(fig)
    draw(fig, store, width, title)
    try:
        fig.savefig(path)
    except OSError as err:
        raise PlotError("cannot write %s: %s" % (path, err))
    return path


def _folder(path):
    folder = os.path.dirname(os.path.abspath(path))
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as err:
        raise PlotError("cannot create the folder of %s: %s" % (path, err))

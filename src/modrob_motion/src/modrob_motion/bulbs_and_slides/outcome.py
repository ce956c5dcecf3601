"""Judging the result: is a bulb resting in a slide's channel, and how far from where it should be."""
import numpy as np


def on_slide(layout, slide_name, glass_centre, margin=0.005):
    """True when the glass centre lies inside the slide's channel (along, across and above it)."""
    slide = layout.slides[slide_name]
    s, lateral, height = slide.coordinates(glass_centre)
    return (-0.02 <= s <= slide.length + margin and abs(lateral) <= slide.half_width + margin
            and 0.0 <= height <= 2.5 * layout.glass_radius)


def expected_rest(layout, slide_name, bulbs_ahead, socket_first=False):
    """Glass centre of a bulb resting in ``slide_name`` behind ``bulbs_ahead`` other bulbs (glass
    first, as the world places them, or ``socket_first``: turned round, its socket downhill)."""
    slide = layout.slides[slide_name]
    u = slide.uphill
    side = np.array([-u[1], u[0], 0.0])
    side /= np.linalg.norm(side)
    n = np.cross(u, side)
    own = layout.bulb_length - layout.grasp_offset if socket_first else layout.grasp_offset
    s = bulbs_ahead * (layout.bulb_length + 0.001) + own
    return slide.tip + s * u + layout.glass_radius * n


def at_rest(speeds, threshold=0.005):
    """speeds: recent linear speeds (m/s) of a bulb; at rest when all are below the threshold."""
    return len(speeds) > 0 and max(speeds) < threshold


class RestWindow(object):
    """Whether a bulb has been at rest (``at_rest``) over the last ``window`` s of simulated time,
    from its speed sampled at simulated times ``t``. The window counts simulated time, not samples:
    a scenario process starved beside a fast simulation samples less often than it asks for, and
    a count of samples then spans more simulated time than the window, up to the whole timeout.
    The samples judged are those from the newest one at or before the window's start (which
    covers it) to the last, at least ``min_samples`` of them."""

    def __init__(self, window, min_samples=3):
        self.window = window
        self.min_samples = min_samples
        self._samples = []

    def add(self, t, speed):
        self._samples.append((t, speed))
        # keep the newest sample at or before t - window: the rest cover the window
        while len(self._samples) > 1 and self._samples[1][0] <= t - self.window + 1e-9:
            self._samples.pop(0)

    def at_rest(self):
        s = self._samples
        return (len(s) >= self.min_samples and s[-1][0] - s[0][0] >= self.window - 1e-9
                and at_rest([v for _, v in s]))


def fingers_done(positions, goal, efforts, effort_limits, moved, tol=0.002, share=0.8, still=5e-4):
    """Whether a gripper command has taken effect, from one joint_states sample of its fingers:
    every finger within ``tol`` of its goal (open, or closed on nothing), or every finger still
    (``moved``: how far it went since the previous sample, per finger, under ``still``; the caller
    asks for several samples in a row) while pressing with at least ``share`` of its effort limit
    (closed on an object: the grip force is the limit)."""
    positions, goal = np.asarray(positions, float), np.asarray(goal, float)
    if np.all(np.abs(positions - goal) <= tol):
        return True
    if moved is None or effort_limits is None or np.any(~np.isfinite(effort_limits)):
        return False
    return bool(np.all(np.abs(moved) < still)
                and np.all(np.abs(np.asarray(efforts, float)) >= share * np.asarray(effort_limits, float)))

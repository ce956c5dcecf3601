"""Joint trajectories as ros_controllers' joint_trajectory_controller samples them: between two
points a per-joint polynomial whose order follows what both ends specify (QuinticSplineSegment):
positions only -> linear, positions + velocities -> cubic, positions + velocities +
accelerations -> quintic. Before the first segment the start state holds; after the last the
final positions hold with zero velocity.

A long trajectory is built in two parts: :class:`PreparedTrajectory` (every segment, in times
relative to the trajectory's start; pure, any thread, O(points)) and
:meth:`PreparedTrajectory.activate`, which places it in time and joins it to the current state
(O(joints) plus a bisection, in the loop thread). Sampling is a bisection, not a scan."""
import bisect

#: Piece kinds (a segment's polynomial in absolute time, in time relative to ``base``, a hold) are
#: the actuators' segment kinds
from modrob_sim.physics.actuators import ABSOLUTE, HOLD, INF, RELATIVE, eval_polynomial, segment_time


class Piece(object):
    """What ``sample`` does from time ``t`` on, for as long as the same branch of it holds (the C
    World's SEGMENT_PID actuators evaluate it: physics.actuators): for a step starting at t' with
    t' < ``abs_until`` and t' - ``base`` < ``rel_until`` (the same float operations as sample's
    own tests), sample(t') is ``segment.sample(t')`` (ABSOLUTE), ``segment.sample(t' - base)``
    plus ``offsets`` when not None (RELATIVE), or ``positions`` with zero velocity (HOLD)."""
    __slots__ = ("kind", "segment", "base", "offsets", "positions", "abs_until", "rel_until")

    def __init__(self, kind, segment=None, base=0.0, offsets=None, positions=None, abs_until=INF,
                 rel_until=INF):
        self.kind, self.segment, self.base, self.offsets = kind, segment, base, offsets
        self.positions, self.abs_until, self.rel_until = positions, abs_until, rel_until


class State(object):
    __slots__ = ("positions", "velocities", "accelerations")

    def __init__(self, positions, velocities=None, accelerations=None):
        self.positions = list(positions)
        self.velocities = list(velocities) if velocities else None
        self.accelerations = list(accelerations) if accelerations else None


def _coefficients(p0, v0, a0, p1, v1, a1, T, order):
    if T <= 0.0:
        return [p1]
    if order == 1:
        return [p0, (p1 - p0) / T]
    if order == 3:
        return [p0, v0,
                (3.0 * (p1 - p0) - (2.0 * v0 + v1) * T) / T ** 2,
                (-2.0 * (p1 - p0) + (v0 + v1) * T) / T ** 3]
    return [p0, v0, 0.5 * a0,
            (20.0 * (p1 - p0) - (8.0 * v1 + 12.0 * v0) * T - (3.0 * a0 - a1) * T ** 2) / (2.0 * T ** 3),
            (30.0 * (p0 - p1) + (14.0 * v1 + 16.0 * v0) * T
             + (3.0 * a0 - 2.0 * a1) * T ** 2) / (2.0 * T ** 4),
            (12.0 * (p1 - p0) - 6.0 * (v1 + v0) * T - (a0 - a1) * T ** 2) / (2.0 * T ** 5)]


class Segment(object):
    def __init__(self, t0, start, t1, end):
        self.t0, self.t1 = t0, t1
        if start.velocities is not None and end.velocities is not None:
            order = 5 if (start.accelerations is not None and end.accelerations is not None) else 3
        else:
            order = 1
        self.order = order
        n = len(end.positions)
        zeros = [0.0] * n
        v0, v1 = start.velocities or zeros, end.velocities or zeros
        a0, a1 = start.accelerations or zeros, end.accelerations or zeros
        T = t1 - t0
        self.coeffs = [_coefficients(start.positions[i], v0[i], a0[i], end.positions[i], v1[i], a1[i], T,
                                     order)
                       for i in range(n)]

    def sample(self, t):
        s = segment_time(t, self.t0, self.t1)
        out = [eval_polynomial(c, s) for c in self.coeffs]
        return [o[0] for o in out], [o[1] for o in out], [o[2] for o in out]


class Trajectory(object):
    """Segments from ``start_state`` at ``t_start`` through ``points`` ((time, State) pairs with
    absolute times, strictly increasing and > t_start or equal for a jump)."""

    def __init__(self, t_start, start_state, points):
        self.segments = []
        prev_t, prev = t_start, start_state
        for t, st in points:
            self.segments.append(Segment(prev_t, prev, t, st))
            prev_t, prev = t, st
        self._ends = [seg.t1 for seg in self.segments]
        self.start_time = t_start
        self.end_time = prev_t
        self.final = prev

    def sample(self, t):
        """(positions, velocities, accelerations) at absolute time t."""
        if not self.segments:
            n = len(self.final.positions)
            return list(self.final.positions), [0.0] * n, [0.0] * n
        if t >= self.end_time:
            n = len(self.final.positions)
            return list(self.final.positions), [0.0] * n, [0.0] * n
        i = bisect.bisect_right(self._ends, t)
        return self.segments[min(i, len(self.segments) - 1)].sample(t)

    def piece(self, t):
        """The Piece of sample() from ``t`` on."""
        return self.pieces(t, 1)[0]

    def pieces(self, t, n):
        """The Piece of sample() from ``t`` on and those that follow it, at most ``n`` in all: the
        segments in turn, then the final hold (a piece that does not hold for a step start where
        the one before ends is passed over as sample() passes over it)."""
        hold = Piece(HOLD, positions=self.final.positions)
        if not self.segments or t >= self.end_time:
            return [hold]
        i = min(bisect.bisect_right(self._ends, t), len(self.segments) - 1)
        out = [Piece(ABSOLUTE, seg, abs_until=seg.t1) for seg in self.segments[i:i + n]]
        if len(out) < n:
            out.append(hold)
        return out


class PreparedTrajectory(object):
    """The segments between consecutive ``states`` at relative ``times`` (strictly increasing),
    built in any thread; positions of joints the goal does not name are 0 here (activate() adds
    the current desired position, as it adds the continuous joints' 2*pi*k shifts: a constant
    added to both ends of a segment only shifts its positions)."""

    def __init__(self, times, states):
        self.times = list(times)
        self.states = list(states)
        self.segments = [Segment(times[i], states[i], times[i + 1], states[i + 1])
                         for i in range(len(self.times) - 1)]

    def activate(self, start, now, current, offsets):
        """A trajectory that starts at ``now`` from the State ``current`` and reaches the first
        point after ``now`` (points at ``start + time`` <= now are skipped), ``offsets`` added to
        every position; None when every point is in the past."""
        times = self.times
        n = len(times)
        k = bisect.bisect_right(times, now - start)
        while k > 0 and start + times[k - 1] > now:  # the same float comparison as point by point
            k -= 1
        while k < n and start + times[k] <= now:
            k += 1
        if k == n:
            return None
        return _PlacedTrajectory(self, start, now, current, offsets, k)


def _shifted(state, offsets):
    return State([p + o for p, o in zip(state.positions, offsets)], state.velocities, state.accelerations)


class _PlacedTrajectory(object):
    """A PreparedTrajectory placed at ``start``: a first segment from the current state, then the
    prepared segments from point ``k`` on (shared, not copied)."""

    def __init__(self, prepared, start, now, current, offsets, k):
        self._prep = prepared
        self._times = prepared.times
        self._segments = prepared.segments
        self._start = start
        self._k = k
        self._off = list(offsets) if any(offsets) else None
        first = _shifted(prepared.states[k], offsets)
        self._first = Segment(now, current, start + prepared.times[k], first)
        self.start_time = now
        self.end_time = start + prepared.times[-1]
        self.final = _shifted(prepared.states[-1], offsets)

    @property
    def segments(self):
        return [self._first] + self._segments[self._k:]

    def sample(self, t):
        if t >= self.end_time:
            n = len(self.final.positions)
            return list(self.final.positions), [0.0] * n, [0.0] * n
        if t < self._first.t1:
            return self._first.sample(t)
        rel = t - self._start
        i = bisect.bisect_right(self._times, rel, self._k) - 1
        i = min(max(i, self._k), len(self._segments) - 1)
        pos, vel, acc = self._segments[i].sample(rel)
        if self._off is not None:
            pos = [p + o for p, o in zip(pos, self._off)]
        return pos, vel, acc

    def piece(self, t):
        """The Piece of sample() from ``t`` on."""
        return self.pieces(t, 1)[0]

    def pieces(self, t, n):
        """As Trajectory.pieces: the first segment, the prepared ones, then the final hold."""
        hold = Piece(HOLD, positions=self.final.positions)
        if t >= self.end_time:
            return [hold]
        out = []
        nseg = len(self._segments)
        if t < self._first.t1:
            out.append(Piece(ABSOLUTE, self._first, abs_until=min(self._first.t1, self.end_time)))
            i = self._k
        else:
            rel = t - self._start
            i = min(max(bisect.bisect_right(self._times, rel, self._k) - 1, self._k), nseg - 1)
        while len(out) < n and i < nseg:
            out.append(Piece(RELATIVE, self._segments[i], self._start, self._off, abs_until=self.end_time,
                             rel_until=self._times[i + 1] if i + 1 < nseg else INF))
            i += 1
        if len(out) < n:
            out.append(hold)
        return out


def hold_trajectory(t, positions, velocities=None, stop_duration=0.0):
    """What ros_controllers' setHoldPosition builds: hold ``positions``; with a stop duration and
    a moving state, decelerate smoothly to rest over that duration (cubic, ending at
    p + v * d / 2 with zero velocity)."""
    n = len(positions)
    if stop_duration <= 0.0 or not velocities or not any(abs(v) > 0.0 for v in velocities):
        return Trajectory(t, State(positions), [])
    end = [p + v * stop_duration / 2.0 for p, v in zip(positions, velocities)]
    return Trajectory(t, State(positions, velocities), [(t + stop_duration, State(end, [0.0] * n))])

"""The camera network's logic, without ROS: per camera, images (with the camera pose at the image's
time: given, or from the joint angles at that time) become ball detections and floor estimates;
the estimates are fused; every camera is aimed at the fused position (ahead by the estimated
velocity); when nothing has been seen for ``lost_time`` the cameras scan their share of the floor
(ScanPlan); every image's footprint marks the coverage grid."""
import bisect
from collections import Counter, deque, namedtuple

import numpy as np

from ptrz_camera import pinhole
from ptrz_camera.tracking import coverage, localize, scan_plan, segment

#: ``ray``: (origin, unit direction) in the world of the ray through the detected pixel (None
#: without a detection); ``pose``: the camera pose the image was taken from
#: ``edge``: distance of the blob's centre from the image's nearest border, in radii of a whole
#: ball's image at the estimated range (inf without an estimate)
#: ``rate``: the camera's fastest pan/tilt speed at t (rad/s; 0 when unknown); ``streak``: how
#: many of the camera's images up to this one in a row had a detection
Observation = namedtuple("Observation", "t detection estimate ray pose edge rate streak")


class Camera(object):
    def __init__(self, name, chain):
        self.name = name
        self.chain = chain
        self.joint_times = deque(maxlen=400)
        self.joint_values = deque(maxlen=400)
        self.joint_rates = deque(maxlen=400)
        self.last = None              # last Observation with a detection
        self.streak = 0               # images in a row with a detection
        self.command = None           # (pan, tilt)
        self.q = {}

    def add_joints(self, t, q, v=None):
        """Joint positions ``q`` (and velocities ``v``, dicts) at time t."""
        if self.joint_times and t < self.joint_times[-1]:
            self.joint_times.clear()          # time went back (simulation reset)
            self.joint_values.clear()
            self.joint_rates.clear()
        if self.joint_times and t == self.joint_times[-1]:
            return
        self.joint_times.append(t)
        self.joint_values.append(dict(q))
        self.joint_rates.append(dict(v) if v else None)
        self.q = dict(q)

    def joints_at(self, t, max_gap=None):
        """Joint angles at time t, between the two samples around it: cubic (Hermite) from their
        positions and velocities when both have velocities, else linear. Outside the samples the
        nearest one; None before any are known, and with ``max_gap`` (s) also when t is not
        between two samples at most that far apart."""
        if not self.joint_times:
            return None
        times = list(self.joint_times)
        i = bisect.bisect_left(times, t)
        if i < len(times) and times[i] == t:
            return self.joint_values[i]
        if i <= 0 or i >= len(times):
            if max_gap is not None:
                return None
            return self.joint_values[0] if i <= 0 else self.joint_values[-1]
        t0, t1 = times[i - 1], times[i]
        h = t1 - t0
        if max_gap is not None and h > max_gap:
            return None
        a = (t - t0) / h
        q0, q1 = self.joint_values[i - 1], self.joint_values[i]
        v0, v1 = self.joint_rates[i - 1], self.joint_rates[i]
        if v0 is None or v1 is None:
            return {k: q0[k] + a * (q1.get(k, q0[k]) - q0[k]) for k in q0}
        h00, h10 = 2 * a ** 3 - 3 * a ** 2 + 1, a ** 3 - 2 * a ** 2 + a
        h01, h11 = -2 * a ** 3 + 3 * a ** 2, a ** 3 - a ** 2
        return {k: h00 * q0[k] + h10 * h * v0.get(k, 0.0) + h01 * q1.get(k, q0[k]) + h11 * h * v1.get(k, 0.0)
                for k in q0}

    def speed_at(self, t, joints=("pan", "tilt")):
        """Fastest speed (rad/s) of ``joints`` at the joint sample nearest to t (0 when unknown)."""
        if not self.joint_times:
            return 0.0
        times = list(self.joint_times)
        i = min(bisect.bisect_left(times, t), len(times) - 1)
        if i > 0 and abs(times[i - 1] - t) < abs(times[i] - t):
            i -= 1
        rates = [r for r in (self.joint_rates[max(0, i - 1)], self.joint_rates[i]) if r]
        return max([abs(r.get(j, 0.0)) for r in rates for j in joints] or [0.0])

    def joints_until(self):
        """Time of the newest joint sample (None before any)."""
        return self.joint_times[-1] if self.joint_times else None


class Network(object):
    def __init__(self, chains, floor, ball_radius=0.11, finder=None, lead=0.25, lost_time=2.0,
                 fuse_window=0.002, sigma_px=1.0, resolution=0.1, stale_time=20.0, min_visible=0.8,
                 max_residual=0.05, edge_margin=3.0, max_wait=0.3, live_time=1.0, min_streak=3):
        """``min_visible``: a blob smaller than this share of a whole ball's image at the estimated
        range is a ball partly hidden (behind a robot, a post): no floor estimate from it.
        ``fuse_window`` (s): images this close in time are one image time (one render batch);
        ``max_residual`` (m) and ``edge_margin`` (ball radii): see :meth:`check`; ``max_wait``
        (s of image time): how long an image time waits for the other cameras' images of it;
        ``live_time`` (s): a camera without images for that long holds no image time back."""
        self.cameras = {name: Camera(name, chain) for name, chain in chains.items()}
        self.order = list(chains)
        self.floor = floor
        self.radius = ball_radius
        self.finder = finder or segment.BallFinder()
        self.lead = lead
        self.lost_time = lost_time
        self.window = fuse_window
        self.max_residual = max_residual
        self.edge_margin = edge_margin
        self.max_wait = max_wait
        self.min_streak = min_streak
        self.live_time = live_time
        self.groups = {}              # image time -> {camera: Observation}
        self.done_t = -np.inf         # the newest image time fused (or rejected)
        self.latest = {}              # camera -> time of its newest image
        self.counts = Counter()       # verdicts of fuse_ready per image time with a detection
        self.sigma_px = sigma_px
        self.min_visible = min_visible
        self.grid = coverage.CoverageGrid(floor[0], floor[1], floor[2], floor[3], resolution, stale_time)
        xy = [tuple(chain.pose({})[1][:2]) for chain in chains.values()]
        self.plan = scan_plan.ScanPlan(xy, floor)
        self.fused = None             # (t, FloorEstimate) published last
        self.aim = None               # (t, FloorEstimate) the cameras follow (every image time's)
        self.sources = []             # [(camera, Observation)] of the last fused estimate
        self.velocity = np.zeros(2)
        self.mode = "scanning"

    def on_joints(self, name, t, q, v=None):
        self.cameras[name].add_joints(t, q, v)

    def on_image(self, name, t, rgb, intr, pose=None):
        """Process one image taken at time t from ``pose`` ((R, t) of the camera link in the
        world; default: forward kinematics of the joint angles interpolated to t); returns the
        Observation (detection may be None), or None when the pose is not known."""
        cam = self.cameras[name]
        if pose is None:
            q = cam.joints_at(t)
            if q is None:
                return None
            pose = cam.chain.pose(q)
        poly = coverage.footprint(pose, intr)
        if poly is not None:
            self.grid.mark(poly, t)
        det = self.finder.find(rgb)
        est = None
        ray = None
        edge = np.inf
        if det is not None:
            ray = (pose[1], pose[0].dot(pinhole.ray(intr, det.u, det.v)))
            est = localize.floor_estimate(pose, intr, det.u, det.v, self.radius, self.sigma_px)
            if est is not None and not self.plausible_size(pose, intr, est, det.area):
                est = None
            if est is not None:
                r_px = np.sqrt(self.expected_area(pose, intr, est) / np.pi)
                edge = min(det.u, intr.width - det.u, det.v, intr.height - det.v) / max(r_px, 1e-6)
        cam.streak = cam.streak + 1 if det is not None else 0
        obs = Observation(t, det, est, ray, pose, edge, cam.speed_at(t), cam.streak)
        if est is not None:
            cam.last = obs
        self._group(name, obs)
        return obs

    def expected_area(self, pose, intr, est):
        """Area (px) of a whole ball's image at the range of the estimate."""
        rng = np.linalg.norm(np.append(est.xy, self.radius) - pose[1])
        return np.pi * (intr.fx * self.radius / rng) ** 2

    def plausible_size(self, pose, intr, est, area):
        """The blob is a whole ball at the estimated range: much larger is something else; smaller
        is a ball partly hidden, whose centroid is the centre of its visible part, not of the ball
        (on the rendered images of a 30 s three-camera run every estimate 3-9 cm off came from a
        blob of 0.22-0.66 of a whole ball's area; the median blob measures 0.98 of it)."""
        expected = self.expected_area(pose, intr, est)
        return self.min_visible * expected <= area <= 4.0 * expected + 4.0

    def _group(self, name, obs):
        """File the observation with those of the other cameras' images of the same time."""
        key = next((k for k in self.groups if abs(k - obs.t) <= self.window), obs.t)
        self.groups.setdefault(key, {})[name] = obs
        self.latest[name] = max(self.latest.get(name, obs.t), obs.t)

    def _due(self):
        """Image times whose group is complete: every camera that delivers images has one of that
        time or later (a camera without an image for ``live_time`` does not hold the others
        back), or a newer image is already ``max_wait`` later."""
        if not self.latest:
            return []
        newest = max(self.latest.values())
        live = [t for t in self.latest.values() if t >= newest - self.live_time]
        done = min(live)
        out = []
        for key in sorted(self.groups):
            if key <= self.done_t + self.window:
                del self.groups[key]             # older than what was published: too late
            elif key <= done + self.window or newest - key > self.max_wait:
                out.append(key)
        return out

    def fuse_ready(self):
        """[(time, fused estimate, [(camera, Observation)])] of each image time whose images are
        all in (oldest first): the estimates of the cameras' images of that one time (the
        renderer draws every camera of a batch at one time), combined by their information; a
        time whose estimates are not reliable (``check``) gives none. The reason of each verdict
        is counted in ``counts``."""
        out = []
        for key in self._due():
            group = self.groups.pop(key)
            self.done_t = key
            sources = [(n, o) for n, o in sorted(group.items()) if o.estimate is not None]
            if not any(o.detection is not None for o in group.values()):
                continue
            self.counts["detected"] += 1
            if sources:          # the cameras follow every estimate, also one not published
                self._follow(key, localize.fuse([o.estimate for _n, o in sources]))
            sources, why = self.check(sources)
            if why:
                self.counts[why] += 1
                continue
            est = localize.fuse([o.estimate for _n, o in sources])
            self.counts["published"] += 1
            self.sources = sources
            t = max(o.t for _n, o in sources)
            self.fused = (t, est)
            out.append((t, est, sources))
        return out

    def _follow(self, t, est):
        if self.aim is not None:
            dt = t - self.aim[0]
            if 1e-3 < dt < 1.0:
                v = (est.xy - self.aim[1].xy) / dt
                self.velocity = 0.6 * self.velocity + 0.4 * v
            elif dt >= 1.0:
                self.velocity = np.zeros(2)
        self.aim = (t, est)

    def fuse(self, t=None):
        """The newest (time, fused estimate) of :meth:`fuse_ready`, or None when no new one."""
        out = self.fuse_ready()
        return out[-1][:2] if out else None

    def check(self, sources):
        """(sources to use, None) or (None, reason): the estimates of one image time are used when
        the rays of two or more cameras pass within ``max_residual`` of one point (with three or
        more, one camera whose ray is off is left out if the others agree), or from one camera
        alone. Only cameras that have locked on count (the ball in at least ``min_streak`` of
        their images in a row: not while a camera first slews to it) and whose ball is not within
        ``edge_margin`` radii of its ball image of the image's border."""
        if not sources:
            return None, "no_estimate"
        locked = [(n, o) for n, o in sources if o.streak >= self.min_streak]
        if not locked:
            return None, "rejected_not_locked"
        inside = [(n, o) for n, o in locked if o.edge >= self.edge_margin]
        if not inside:
            return None, "rejected_edge"
        sources = inside
        if len(sources) == 1:
            return sources, None
        rr = localize.ray_residual([o.ray for _n, o in sources])
        if rr is not None and rr[1] <= self.max_residual:
            return sources, None
        if len(sources) >= 3:
            best = None
            for i in range(len(sources)):
                rest = sources[:i] + sources[i + 1:]
                r = localize.ray_residual([o.ray for _n, o in rest])
                if r is not None and r[1] <= self.max_residual and (best is None or r[1] < best[0]):
                    best = (r[1], rest)
            if best is not None:
                self.counts["left_out"] += 1
                return best[1], None
        return None, "rejected_residual"

    def commands(self, t, settled):
        """{camera: (pan, tilt)}: aim at the ball (tracking) or at the scan points (scanning).
        ``settled``: {camera: bool} whether the camera has reached its last command."""
        out = {}
        if self.aim is not None and abs(t - self.aim[0]) <= self.lost_time:
            self.mode = "tracking"
            xy = self.aim[1].xy + self.velocity * self.lead
            target = (xy[0], xy[1], self.radius)
            for name, cam in self.cameras.items():
                out[name] = cam.chain.aim(target, cam.q)
        else:
            self.mode = "scanning"
            for i, name in enumerate(self.order):
                cam = self.cameras[name]
                target = self.plan.target(i, t, settled.get(name, False))
                out[name] = cam.chain.aim(target, cam.q)
        for name, cmd in out.items():
            if cmd is not None:
                self.cameras[name].command = cmd
        return {k: v for k, v in out.items() if v is not None}

"""The camera network's logic, without ROS: per camera, images (with the camera pose at the image's
time: given, or from the joint angles at that time) become ball detections and floor estimates;
the estimates are fused; every camera is aimed at the fused position (ahead by the estimated
velocity); when nothing has been seen for ``lost_time`` the cameras scan their share of the floor
(ScanPlan); every image's footprint marks the coverage grid."""
import bisect
from collections import deque, namedtuple

import numpy as np

from ptrz_camera.tracking import coverage, localize, scan_plan, segment

Observation = namedtuple("Observation", "t detection estimate")


class Camera(object):
    def __init__(self, name, chain):
        self.name = name
        self.chain = chain
        self.joint_times = deque(maxlen=400)
        self.joint_values = deque(maxlen=400)
        self.last = None              # last Observation with a detection
        self.command = None           # (pan, tilt)
        self.q = {}

    def add_joints(self, t, q):
        if self.joint_times and t < self.joint_times[-1]:
            self.joint_times.clear()          # time went back (simulation reset)
            self.joint_values.clear()
        self.joint_times.append(t)
        self.joint_values.append(dict(q))
        self.q = dict(q)

    def joints_at(self, t):
        """Joint angles at time t, linearly interpolated; None before any are known."""
        if not self.joint_times:
            return None
        times = list(self.joint_times)
        i = bisect.bisect_left(times, t)
        if i <= 0:
            return self.joint_values[0]
        if i >= len(times):
            return self.joint_values[-1]
        t0, t1 = times[i - 1], times[i]
        a = 0.0 if t1 <= t0 else (t - t0) / (t1 - t0)
        q0, q1 = self.joint_values[i - 1], self.joint_values[i]
        return {k: q0[k] + a * (q1.get(k, q0[k]) - q0[k]) for k in q0}


class Network(object):
    def __init__(self, chains, floor, ball_radius=0.11, finder=None, lead=0.25, lost_time=2.0,
                 fuse_window=0.06, sigma_px=1.0, resolution=0.1, stale_time=20.0, min_visible=0.7):
        """``min_visible``: a blob smaller than this share of a whole ball's image at the estimated
        range is a ball partly hidden (behind a robot, a post): no floor estimate from it."""
        self.cameras = {name: Camera(name, chain) for name, chain in chains.items()}
        self.order = list(chains)
        self.floor = floor
        self.radius = ball_radius
        self.finder = finder or segment.BallFinder()
        self.lead = lead
        self.lost_time = lost_time
        self.window = fuse_window
        self.sigma_px = sigma_px
        self.min_visible = min_visible
        self.grid = coverage.CoverageGrid(floor[0], floor[1], floor[2], floor[3], resolution, stale_time)
        xy = [tuple(chain.pose({})[1][:2]) for chain in chains.values()]
        self.plan = scan_plan.ScanPlan(xy, floor)
        self.fused = None             # (t, FloorEstimate)
        self.velocity = np.zeros(2)
        self.mode = "scanning"

    def on_joints(self, name, t, q):
        self.cameras[name].add_joints(t, q)

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
        if det is not None:
            est = localize.floor_estimate(pose, intr, det.u, det.v, self.radius, self.sigma_px)
            if est is not None and not self.plausible_size(pose, intr, est, det.area):
                est = None
        obs = Observation(t, det, est)
        if est is not None:
            cam.last = obs
        return obs

    def plausible_size(self, pose, intr, est, area):
        """The blob is a whole ball at the estimated range: much larger is something else; smaller
        is a ball partly hidden, whose centroid is the centre of its visible part, not of the ball
        (on the rendered images of a 30 s three-camera run every estimate 3-9 cm off came from a
        blob of 0.22-0.66 of a whole ball's area; the median blob measures 0.98 of it)."""
        rng = np.linalg.norm(np.append(est.xy, self.radius) - pose[1])
        expected = np.pi * (intr.fx * self.radius / rng) ** 2
        return self.min_visible * expected <= area <= 4.0 * expected + 4.0

    def fuse(self, t):
        """(time, fused estimate) of the newest detections (those within ``fuse_window`` of the
        newest one: the renderer renders all cameras in one pass), or None when nothing new
        arrived since the last call. The time is the newest image's."""
        lasts = [c.last for c in self.cameras.values() if c.last is not None]
        if not lasts:
            return None
        newest = max(o.t for o in lasts)
        if self.fused is not None and newest <= self.fused[0]:
            return None
        t = newest
        est = localize.fuse([o.estimate for o in lasts if o.t >= newest - self.window])
        if est is None:
            return None
        if self.fused is not None:
            dt = t - self.fused[0]
            if 1e-3 < dt < 1.0:
                v = (est.xy - self.fused[1].xy) / dt
                self.velocity = 0.6 * self.velocity + 0.4 * v
            elif dt >= 1.0:
                self.velocity = np.zeros(2)
        self.fused = (t, est)
        return t, est

    def commands(self, t, settled):
        """{camera: (pan, tilt)}: aim at the ball (tracking) or at the scan points (scanning).
        ``settled``: {camera: bool} whether the camera has reached its last command."""
        out = {}
        if self.fused is not None and abs(t - self.fused[0]) <= self.lost_time:
            self.mode = "tracking"
            xy = self.fused[1].xy + self.velocity * self.lead
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

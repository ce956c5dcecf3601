"""A lap of the parking lot with pure pursuit, Ackermann and the obstacle stop, on the in-process
VehicleSim with the analytic HDL-32E (synthetic_scan) -- the benchmark and tier-1 harness. The
ROS node (ros_lap.py) runs the same PurePursuit / ObstacleDetector / StopGuard on /odom and
/velodyne_points2."""
import math
import random

from polaris_description import parking_lot
from polaris_description.ackermann import Ackermann
from polaris_description.obstacle import BODY_X, ObstacleDetector, StopGuard
from polaris_description.pure_pursuit import PurePursuit
from polaris_description.synthetic_scan import scan
from polaris_description.vehicle_sim import PARKING_LOT, VehicleSim

CONE_BASE_RADIUS = parking_lot.CONE_BASE / 2.0 * math.sqrt(2.0)
BODY_HALF_WIDTH = 0.75


def seeded_cone(seed, waypoints=None):
    """A cone position on the lap, away from the start: (x, y)."""
    rng = random.Random(seed)
    wps = waypoints or parking_lot.lap_waypoints(1.0)
    i = rng.randrange(12, len(wps) - 6)
    x, y = wps[i]
    return (x + rng.uniform(-0.3, 0.3), y + rng.uniform(-0.3, 0.3))


def gap_to(cone, x, y, yaw):
    """Clearance (m) between the vehicle's footprint and the cone's base."""
    dx, dy = cone[0] - x, cone[1] - y
    c, s = math.cos(yaw), math.sin(yaw)
    lx, ly = c * dx + s * dy, -s * dx + c * dy
    ex = max(BODY_X[0] - lx, 0.0, lx - BODY_X[1])
    ey = max(abs(ly) - BODY_HALF_WIDTH, 0.0)
    return math.hypot(ex, ey) - CONE_BASE_RADIUS


def run_lap(cone=None, speed=1.5, lookahead=3.0, max_time=90.0, log=None, seed=0):
    """Drive the lap from the spawn point (0, 0, heading +x). Returns a result dict."""
    wps = parking_lot.lap_waypoints(1.0)
    sim = VehicleSim(world_file=PARKING_LOT, pid_config=5, seed=seed)
    if cone is not None:
        sim.world.add_sdf(parking_lot.cone_model_sdf("cone_on_path", cone[0], cone[1]))
    # from the spawn point onto the lap, once round, ending where the lap began
    pp = PurePursuit([(0.0, 0.0)] + wps + [wps[0]], lookahead=lookahead, speed=speed, closed=False)
    ack = Ackermann()
    det = ObstacleDetector()
    guard = StopGuard()
    cones = [(c.x, c.y) for c in parking_lot.CONES] + ([cone] if cone is not None else [])
    res = {"samples": [], "max_cross_track": 0.0, "min_gap": math.inf, "stopped": False,
           "completed": False, "stop_distance": None, "detected_at": None}
    state = {"next_scan": 0.0, "stopped_since": None}

    def controller(s):
        x, y, yaw = s["x"], s["y"], s["yaw"]
        res["samples"].append(s)
        if s["t"] >= state["next_scan"]:
            state["next_scan"] += 0.1                                 # the lidar's 10 Hz
            kappa = ack._last_curvature
            d = det.distance(scan((x, y, yaw), cones), kappa)
            if guard.update(d) and res["detected_at"] is None:
                res["detected_at"] = (s["t"], d)
                if log:
                    log("t %.1f s: obstacle %.2f m ahead of the bumper: stopping" % (s["t"], d))
        if guard.stopped:
            v, w = 0.0, 0.0
            if s["speed"] < 0.02:
                state["stopped_since"] = state["stopped_since"] or s["t"]
                if s["t"] - state["stopped_since"] > 1.0:
                    res["stopped"] = True
                    return False
        else:
            v, w = pp.update(x, y, yaw)
            if pp.index > 3:
                res["max_cross_track"] = max(res["max_cross_track"], pp.cross_track(x, y))
            if pp.done:
                res["completed"] = True
                return False
        c = ack.command(v, w) if v != 0.0 else ack.command(0.0, 0.0)
        sim.command(steer_left=c.steer_left, steer_right=c.steer_right, rear_left=c.rear_left,
                    rear_right=c.rear_right)
        if cone is not None:
            res["min_gap"] = min(res["min_gap"], gap_to(cone, x, y, yaw))
        if log and int(s["t"] * 50) % 500 == 0:
            log("t %5.1f s  x %6.2f  y %6.2f  speed %.2f m/s  waypoint %d/%d"
                % (s["t"], x, y, s["speed"], pp.index, len(pp.path)))
        return True

    sim.run(max_time, controller=controller, every=0.02)
    return res

"""The seed's PID experiment (section 5.3.2, table 2, figures 7 and 8), as a pure driver.

2 rad/s on both rear wheels with no steering; once the speed has settled (or after
``straight_time`` s) 0.7 rad on both steering blocks until the heading has turned
``turn_until`` rad, then straight again. The driver only writes joint commands, so the same
script drives the in-process VehicleSim (figures, tests) and the ROS controllers (demo).
"""
import math

from polaris_description import geometry as G

WHEEL_RATE = 2.0          # rad/s: the seed's omega
EXPECTED_SPEED = WHEEL_RATE * G.WHEEL_RADIUS   # 0.64 m/s
STEER = 0.7               # rad


class SeedExperiment(object):
    """Call ``step(state)`` with the vehicle state (t, yaw); it returns the joint commands to send
    (dict of geometry.JOINTS keys) and records the phase changes in ``events``."""

    def __init__(self, straight_time=10.0, turn_until=math.radians(85.0), after_time=8.0, max_turn_time=30.0):
        self.straight_time = straight_time
        self.turn_until = turn_until
        self.after_time = after_time
        self.max_turn_time = max_turn_time
        self.phase = "straight"
        self.yaw0 = None
        self.t_turn = None
        self.t_after = None
        self.events = []

    def step(self, state):
        t, yaw = state["t"], state["yaw"]
        if self.yaw0 is None:
            self.yaw0 = yaw
        turned = abs(math.atan2(math.sin(yaw - self.yaw0), math.cos(yaw - self.yaw0)))
        if self.phase == "straight" and t >= self.straight_time:
            self.phase, self.t_turn = "turn", t
            self.events.append((t, "steer %.1f rad" % STEER))
        elif self.phase == "turn" and (turned >= self.turn_until or t - self.t_turn > self.max_turn_time):
            self.phase, self.t_after = "after", t
            self.events.append((t, "straighten (turned %.0f deg)" % math.degrees(turned)))
        elif self.phase == "after" and t - self.t_after >= self.after_time:
            self.phase = "done"
        steer = STEER if self.phase == "turn" else 0.0
        return {"rear_left": WHEEL_RATE, "rear_right": WHEEL_RATE, "steer_left": steer, "steer_right": steer}

    @property
    def done(self):
        return self.phase == "done"


def summarize(samples, exp):
    """Figures of one run: mean speed over the last 4 s of the straight phase, the heading change
    of the turn and the final heading rate."""
    t_turn = exp.t_turn if exp.t_turn is not None else samples[-1]["t"]
    flat = [s["speed"] for s in samples if t_turn - 4.0 <= s["t"] < t_turn]
    mean_speed = sum(flat) / len(flat) if flat else float("nan")
    yaw0 = samples[0]["yaw"]
    end = samples[-1]
    heading = math.degrees(math.atan2(math.sin(end["yaw"] - yaw0), math.cos(end["yaw"] - yaw0)))
    return {"mean_speed": mean_speed, "speed_error": mean_speed / EXPECTED_SPEED - 1.0,
            "heading_change_deg": heading, "final_yaw_rate": end["yaw_rate"],
            "turn_started": exp.t_turn, "turn_ended": exp.t_after}

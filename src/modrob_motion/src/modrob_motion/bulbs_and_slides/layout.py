"""The Bulbs and Slides numbers, read from modrob_description/worlds/bulbs_and_slides_layout.yaml
(written by the world generator together with the .world files, so they always agree)."""
import math
import os

import numpy as np
import yaml

from modrob_motion.bulbs_and_slides import ScenarioError

SCENARIOS = ("one_robot", "two_robots")


def default_layout_file():
    import rospkg
    try:
        return os.path.join(rospkg.RosPack().get_path("modrob_description"), "worlds",
                            "bulbs_and_slides_layout.yaml")
    except rospkg.ResourceNotFound:
        raise ScenarioError("package modrob_description not found: source scripts/env.sh")


class Slide(object):
    def __init__(self, name, d):
        self.name = name
        self.tip = np.array(d["tip"], dtype=float)
        self.high_end = np.array(d["high_end"], dtype=float)
        self.half_width = float(d["half_width"])
        self.length = float(d["length"])

    @property
    def uphill(self):
        v = self.high_end - self.tip
        return v / np.linalg.norm(v)

    def coordinates(self, point):
        """(s along the floor from the tip, lateral offset from the centre-line, height above the
        floor plane) of a world point."""
        u = self.uphill
        side = np.array([-u[1], u[0], 0.0])
        side /= np.linalg.norm(side)
        n = np.cross(u, side)
        d = np.asarray(point, dtype=float) - self.tip
        return float(d.dot(u)), float(d.dot(side)), float(d.dot(n))


class Layout(object):
    """One scenario's layout: robots [(order, base)], slides {name: Slide}, bulb geometry, the
    release point over the blue slide and (two robots) the cradle point."""

    def __init__(self, data, scenario, path="<layout>"):
        if scenario not in SCENARIOS:
            raise ScenarioError("unknown scenario '%s'; choose one of %s" % (scenario, ", ".join(SCENARIOS)))
        try:
            lay = data["layouts"][scenario]
            self.scenario = scenario
            self.world = lay["world"]
            self.robots = [(list(r["order"]), [float(v) for v in r["base"]]) for r in lay["robots"]]
            self.slides = {n: Slide(n, d) for n, d in lay["slides"].items()}
            self.place_point = np.array(lay["place_point"], dtype=float)
            self.cradle_point = np.array(lay["cradle_point"], dtype=float) if "cradle_point" in lay else None
            self.safety_distance = float(lay.get("safety_distance", 0.0))
            b = data["bulb"]
            self.glass_radius = float(b["glass_radius"])
            self.glass_length = float(b["glass_length"])
            self.socket_length = float(b["socket_length"])
            self.grasp_offset = float(b["grasp_offset"])
            self.bulbs_on = dict(lay.get("bulbs_on") or {})   # bulb name: slide it waits on
            self.incline = float(data["slide_incline"])
        except (KeyError, TypeError, ValueError) as exc:
            raise ScenarioError("layout file %s lacks or mangles %s: regenerate it with "
                                "modrob_description/worlds/generate_bulbs_and_slides.py" % (path, exc))
        for need in ("red_slide", "blue_slide"):
            if need not in self.slides:
                raise ScenarioError("layout file %s has no %s for %s" % (path, need, scenario))

    def bulbs_waiting_on(self, slide_name):
        """How many bulbs the world puts on ``slide_name`` (they wait at its tip, one behind the other)."""
        return sum(1 for s in self.bulbs_on.values() if s == slide_name)

    @property
    def bulb_length(self):
        return self.glass_length + self.socket_length

    @classmethod
    def load(cls, scenario, path=None):
        path = path or default_layout_file()
        try:
            with open(path) as fh:
                data = yaml.safe_load(fh)
        except OSError as exc:
            raise ScenarioError("cannot read the layout file %s: %s" % (path, exc))
        except yaml.YAMLError as exc:
            raise ScenarioError("layout file %s is not valid YAML: %s" % (path, exc))
        if not isinstance(data, dict):
            raise ScenarioError("layout file %s does not hold a mapping" % path)
        return cls(data, scenario, path)


def quat_to_matrix(q):
    x, y, z, w = q
    n = math.sqrt(x * x + y * y + z * z + w * w) or 1.0
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def bulb_grasp_point(layout, pose):
    """(glass centre, unit axis) of a bulb whose model frame is at ``pose`` ((x,y,z), (qx,qy,qz,qw))."""
    r = quat_to_matrix(pose[1])
    axis = r[:, 0]
    return np.asarray(pose[0], dtype=float) + layout.grasp_offset * axis, axis

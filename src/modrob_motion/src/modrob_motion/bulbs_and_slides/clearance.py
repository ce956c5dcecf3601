"""How close two robots come to each other (pure geometry, no ROS).

Each robot is reduced to its skeleton: line segments from every link frame to its parent link's frame
(the kinematic tree of its URDF). The clearance of two robots is the smallest distance between a
segment of one and a segment of the other; the links' own thickness (about 0.05 m radius for the
modules) still has to fit into it. Links that the simulator does not report (e.g. merged fixed links)
are skipped: the segment then runs to the nearest reported ancestor.
"""
import xml.etree.ElementTree as ET

import numpy as np

from modrob_motion.bulbs_and_slides import ScenarioError


def urdf_parents(urdf_xml):
    """{child link: parent link} of every joint in a URDF string."""
    try:
        root = ET.fromstring(urdf_xml)
    except ET.ParseError as exc:
        raise ScenarioError("robot_description is not valid XML: %s" % exc)
    parents = {}
    for joint in root.findall("joint"):
        p, c = joint.find("parent"), joint.find("child")
        if p is None or c is None:
            raise ScenarioError("URDF joint '%s' has no parent or child link" % joint.get("name"))
        parents[c.get("link")] = p.get("link")
    return parents


def skeleton(parents, positions):
    """Segments (name, start, end) of a robot's skeleton. ``positions``: {link: (x, y, z)} of the links
    the simulator reports; a link's segment runs to its nearest reported ancestor."""
    segs = []
    for link, pos in positions.items():
        up = parents.get(link)
        while up is not None and up not in positions:
            up = parents.get(up)
        if up is not None:
            segs.append(("%s-%s" % (up, link), np.asarray(positions[up], float), np.asarray(pos, float)))
    if not segs:
        segs = [(link, np.asarray(p, float), np.asarray(p, float)) for link, p in positions.items()]
    return segs


def segment_distance(p1, q1, p2, q2):
    """Smallest distance between segments p1-q1 and p2-q2 (3D; degenerate segments allowed)."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, f = float(d1 @ d1), float(d2 @ d2), float(d2 @ r)
    eps = 1e-12
    if a <= eps and e <= eps:
        return float(np.linalg.norm(r))
    if a <= eps:
        s, t = 0.0, min(1.0, max(0.0, f / e))
    else:
        c = float(d1 @ r)
        if e <= eps:
            t, s = 0.0, min(1.0, max(0.0, -c / a))
        else:
            b = float(d1 @ d2)
            den = a * e - b * b
            s = min(1.0, max(0.0, (b * f - c * e) / den)) if den > eps else 0.0
            t = (b * s + f) / e
            if t < 0.0:
                t, s = 0.0, min(1.0, max(0.0, -c / a))
            elif t > 1.0:
                t, s = 1.0, min(1.0, max(0.0, (b - c) / a))
    return float(np.linalg.norm((p1 + s * d1) - (p2 + t * d2)))


def clearance(segs_a, segs_b):
    """(distance, name in a, name in b) of the closest pair of skeleton segments."""
    best = (float("inf"), None, None)
    for na, pa, qa in segs_a:
        for nb, pb, qb in segs_b:
            d = segment_distance(pa, qa, pb, qb)
            if d < best[0]:
                best = (d, na, nb)
    return best


def positions_by_model(names, points, models):
    """Split /gazebo/link_states (``model::link`` names, positions) into {model: {link: xyz}}."""
    out = {m: {} for m in models}
    for name, p in zip(names, points):
        model, sep, link = name.partition("::")
        if sep and model in out:
            out[model][link] = p
    return out

"""The parking lot world (after the seed's Tietotekniikka-talo lot): pure geometry + SDF text.

A flat asphalt lot with painted bay lines, two ramps of different incline (8 and 15 degrees,
0.5 and 0.8 m high, along +x) and street cones. Everything a test or the waypoint follower needs to know
about the world (cone positions, ramp extents, the lap) comes from here, and
``worlds/parking_lot.world`` is written from it (``python3 -m polaris_description.parking_lot``),
so the world file and the code cannot disagree (a unit test checks the file is current).
"""
import math
from collections import namedtuple

Ramp = namedtuple("Ramp", "name x_start y incline_deg height plateau width")
Cone = namedtuple("Cone", "name x y")

LOT_X = (-10.0, 34.0)
LOT_Y = (-14.0, 20.0)
# two ramps of different incline, both climbed along +x from x_start
RAMPS = (
    Ramp("ramp_gentle", 2.0, -8.0, 8.0, 0.5, 3.0, 3.0),
    Ramp("ramp_steep", 18.0, -8.0, 15.0, 0.8, 3.0, 3.0),
)
# street cones at the lot's edges and between the bays (not on the lap)
CONES = (
    Cone("cone_1", -4.0, -3.0),
    Cone("cone_2", -4.0, 3.0),
    Cone("cone_3", 12.0, -4.0),
    Cone("cone_4", 28.0, -4.0),
    Cone("cone_5", 12.0, 16.0),
    Cone("cone_6", 28.0, 16.0),
)
# the lap of the waypoint follower: a rounded rectangle around the central bays, counter-clockwise
LAP_CORNERS = ((0.0, 0.0), (24.0, 0.0), (24.0, 12.0), (0.0, 12.0))
LAP_CORNER_RADIUS = 5.0

CONE_HEIGHT = 0.7
# (radius, z_bottom, z_top) of the stacked cylinders approximating a cone, plus a square base
CONE_STACK = ((0.16, 0.03, 0.25), (0.115, 0.25, 0.48), (0.07, 0.48, CONE_HEIGHT))
CONE_BASE = 0.38


def ramp_length(ramp):
    """Horizontal length of one slope."""
    return ramp.height / math.tan(math.radians(ramp.incline_deg))


def ramp_extent(ramp):
    """(x0, x1): where the ramp starts and ends along x."""
    s = ramp_length(ramp)
    return ramp.x_start, ramp.x_start + 2.0 * s + ramp.plateau


def ramp_surface_height(ramp, x, y):
    """Height of the ramp's top surface at (x, y) (0 off the ramp)."""
    if abs(y - ramp.y) > ramp.width / 2.0:
        return 0.0
    s = ramp_length(ramp)
    x0, x1 = ramp_extent(ramp)
    if x <= x0 or x >= x1:
        return 0.0
    if x < x0 + s:
        return (x - x0) / s * ramp.height
    if x > x1 - s:
        return (x1 - x) / s * ramp.height
    return ramp.height


def lap_waypoints(spacing=1.0):
    """Waypoints of the lap (closed, counter-clockwise, from (LAP_CORNER_RADIUS, 0) along +x),
    about ``spacing`` metres apart."""
    pts = []
    r = LAP_CORNER_RADIUS
    n = len(LAP_CORNERS)
    for i in range(n):
        c0, c1 = LAP_CORNERS[i], LAP_CORNERS[(i + 1) % n]
        dx, dy = c1[0] - c0[0], c1[1] - c0[1]
        length = math.hypot(dx, dy)
        ux, uy = dx / length, dy / length
        start = r
        # straight from (start) to (length - r)
        k = int(math.ceil((length - r - start) / spacing))
        for j in range(k):
            s = start + j * (length - r - start) / k
            pts.append((c0[0] + ux * s, c0[1] + uy * s))
        # quarter circle around the corner c1 (left turn)
        cx, cy = c1[0] - ux * r - uy * r, c1[1] - uy * r + ux * r
        a0 = math.atan2(-ux, uy)  # from the centre to the start of the arc
        m = int(math.ceil(r * math.pi / 2.0 / spacing))
        for j in range(m):
            a = a0 + (math.pi / 2.0) * j / m
            pts.append((cx + r * math.cos(a), cy + r * math.sin(a)))
    return pts


def _box(name, pose, size, rgba, collide=True):
    geom = "<box><size>%g %g %g</size></box>" % size
    col = ("<collision name='%s_collision'><geometry>%s</geometry></collision>" % (name, geom)
           if collide else "")
    return ("<link name='%s'><pose>%s</pose>%s<visual name='%s_visual'><geometry>%s</geometry>"
            "<material><diffuse>%s</diffuse></material></visual></link>"
            % (name, " ".join("%.4f" % v for v in pose), col, name, geom, rgba))


def cone_model_sdf(name, x, y, static=True):
    """A street cone (orange stacked cylinders on a square base) as an SDF <model>."""
    parts = ["<model name='%s'><static>%s</static><pose>%.4f %.4f 0 0 0 0</pose><link name='body'>"
             % (name, "true" if static else "false", x, y)]
    if not static:
        parts.append("<inertial><mass>2.0</mass><pose>0 0 0.2 0 0 0</pose><inertia><ixx>0.03</ixx>"
                     "<iyy>0.03</iyy><izz>0.02</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>"
                     "</inertial>")
    geoms = [("base", "0 0 0.015 0 0 0", "<box><size>%g %g 0.03</size></box>" % (CONE_BASE, CONE_BASE))]
    for i, (r, z0, z1) in enumerate(CONE_STACK):
        geoms.append(("part%d" % i, "0 0 %.4f 0 0 0" % ((z0 + z1) / 2.0),
                      "<cylinder><radius>%g</radius><length>%g</length></cylinder>" % (r, z1 - z0)))
    for gname, pose, geom in geoms:
        parts.append("<collision name='%s'><pose>%s</pose><geometry>%s</geometry></collision>"
                     "<visual name='%s_visual'><pose>%s</pose><geometry>%s</geometry>"
                     "<material><diffuse>1.0 0.35 0.0 1</diffuse></material></visual>"
                     % (gname, pose, geom, gname, pose, geom))
    parts.append("</link></model>")
    return "".join(parts)


def _ramp_model(ramp):
    """Up slope, plateau and down slope as three static boxes (0.2 m thick slabs)."""
    s = ramp_length(ramp)
    a = math.radians(ramp.incline_deg)
    t = 0.2
    x0, x1 = ramp_extent(ramp)
    links = []
    slope_len = math.hypot(s, ramp.height)
    grey = "0.55 0.55 0.5 1"
    # a slab whose top face runs from (x0, 0) to (x0 + s, h): centre below the mid-line by t/2
    for name, xa, sign in (("up", x0, 1.0), ("down", x1 - s, -1.0)):
        cx = xa + s / 2.0 + sign * math.sin(a) * t / 2.0
        cz = ramp.height / 2.0 - math.cos(a) * t / 2.0
        links.append(_box(name, (cx, ramp.y, cz, 0.0, -sign * a, 0.0), (slope_len, ramp.width, t), grey))
    links.append(_box("plateau", ((x0 + s + x1 - s) / 2.0, ramp.y, ramp.height - t / 2.0, 0, 0, 0),
                      (ramp.plateau + 0.02, ramp.width, t), grey))
    return "<model name='%s'><static>true</static>%s</model>" % (ramp.name, "".join(links))


def _lot_model():
    """Asphalt and painted lines: visuals only (flat paint does not change the physics)."""
    links = []
    w, h = LOT_X[1] - LOT_X[0], LOT_Y[1] - LOT_Y[0]
    links.append(_box("asphalt", ((LOT_X[0] + LOT_X[1]) / 2.0, (LOT_Y[0] + LOT_Y[1]) / 2.0, 0.001, 0, 0, 0),
                      (w, h, 0.002), "0.25 0.25 0.27 1", collide=False))
    white = "0.95 0.95 0.95 1"
    k = 0
    # two rows of bays inside the lap (bays 2.5 m wide, 5 m deep), lines along y
    for row_y in (6.0,):
        for i in range(8):
            x = 4.0 + 2.5 * i
            links.append(_box("bay_line_%d" % k, (x, row_y, 0.003, 0, 0, 0), (0.12, 5.0, 0.002), white,
                              collide=False))
            k += 1
        links.append(_box("bay_spine", (4.0 + 2.5 * 3.5, row_y, 0.003, 0, 0, 0), (17.5, 0.12, 0.002), white,
                          collide=False))
    # bays along the north edge, facing the lap
    for i in range(10):
        x = 1.0 + 2.5 * i
        links.append(_box("north_line_%d" % i, (x, 17.5, 0.003, 0, 0, 0), (0.12, 5.0, 0.002), white,
                          collide=False))
    # lot border lines
    cx, cy = (LOT_X[0] + LOT_X[1]) / 2.0, (LOT_Y[0] + LOT_Y[1]) / 2.0
    borders = (("edge_s", (cx, LOT_Y[0] + 0.3), (w - 0.6, 0.15)),
               ("edge_n", (cx, LOT_Y[1] - 0.3), (w - 0.6, 0.15)),
               ("edge_w", (LOT_X[0] + 0.3, cy), (0.15, h - 0.6)),
               ("edge_e", (LOT_X[1] - 0.3, cy), (0.15, h - 0.6)))
    for name, (x, y), (sx, sy) in borders:
        links.append(_box(name, (x, y, 0.003, 0, 0, 0), (sx, sy, 0.002), white, collide=False))
    return "<model name='parking_lot'><static>true</static>%s</model>" % "".join(links)


def world_sdf():
    """The whole world file text."""
    body = [
        "<include><uri>model://ground_plane</uri></include>",
        "<include><uri>model://sun</uri></include>",
        "<physics type='ode'><max_step_size>0.001</max_step_size><real_time_factor>1.0</real_time_factor>"
        "</physics>",
        _lot_model(),
    ]
    body.extend(_ramp_model(r) for r in RAMPS)
    body.extend(cone_model_sdf(c.name, c.x, c.y) for c in CONES)
    return ("<?xml version='1.0'?>\n<!-- generated by python3 -m polaris_description.parking_lot; "
            "do not edit -->\n<sdf version='1.6'><world name='parking_lot'>\n%s\n</world></sdf>\n"
            % "\n".join(body))


def main(argv=None):
    import argparse
    import os
    p = argparse.ArgumentParser(description="Write the parking lot world file.")
    p.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "..", "worlds",
                                                 "parking_lot.world"))
    a = p.parse_args(argv)
    with open(a.out, "w") as f:
        f.write(world_sdf())
    print("wrote %s" % os.path.normpath(a.out))


if __name__ == "__main__":
    main()

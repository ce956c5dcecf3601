#!/usr/bin/env python3
"""Writes the Bulbs and Slides worlds, models and layout (seed 000, section IV-D and appendix).

    python3 generate_bulbs_and_slides.py          # rewrites the files below, from this folder's package

Outputs (all committed; rerun after changing a number here, never edit them by hand):
    worlds/bulbs_and_slides.world               one-robot layout (the 6-DoF arm stands on the table)
    worlds/bulbs_and_slides_two_robots.world    two-robot layout (two 3-DoF arms on floor stands)
    worlds/bulbs_and_slides_layout.yaml         numbers the scenario scripts need (robot bases,
                                                slide tips, bulb geometry, pick and place points)
    models/{bulb,red_slide,blue_slide,doughnut}/model.sdf + model.config, doughnut/meshes/doughnut.obj

Geometry (metres, world frame; table centred at the origin, work surface z = 1.020):
  * table 2.0 x 1.2 m, long sides along x;
  * slides: inclined channels (floor + two side rails) whose centre-lines run along x (parallel to the
    table's long sides), descending towards -x at ALPHA; the last TONGUE_LEN before the tip has no
    rails and a narrow floor (a tongue) so that gripper fingers can reach around the bulb waiting
    there; a low post stops the bulbs at the tip. Red = long (0.60 m), blue = short (0.35 m);
  * bulbs: A60 bulb (60 mm glass, E27 socket). Collision = two stacked cylinders (glass r 30 mm x 65 mm,
    socket r 13.5 mm x 30 mm); they lie in the channels with their axis along the slide, glass first;
  * friction: slide floor mu 0.08 (tan ALPHA = 0.176 > 0.08: a released bulb slides down to the tip),
    bulb mu 1.0 (the gripper's pads, mu 1.2, hold it; the contact uses the smaller of the two, as Gazebo).
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
PKG = os.path.dirname(HERE)

TABLE_TOP = 1.020
TABLE_SIZE = (2.0, 1.2, 0.04)
ALPHA = math.radians(10.0)       # slide incline
TIP_HEIGHT = 0.04                # floor top above the table at the tip
FLOOR_T = 0.01
CHANNEL_W = 0.08                 # between the rails
RAIL_T, RAIL_H = 0.01, 0.025     # rail thickness, height above the floor
TONGUE_LEN, TONGUE_W = 0.10, 0.024
POST = (0.02, 0.024, 0.02)       # stop post at the tip: length, width, height above the floor
SLIDE_MU = 0.08

BULB_GLASS_R, BULB_GLASS_L = 0.030, 0.065
BULB_SOCKET_R, BULB_SOCKET_L = 0.0135, 0.030
BULB_GLASS_M, BULB_SOCKET_M = 0.035, 0.015
BULB_MU = 1.0
BULB_GAP = 0.001                 # spawn gap between neighbouring bulbs

SLIDE_COLOURS = {"red_slide": (0.8, 0.1, 0.1, 1.0), "blue_slide": (0.1, 0.2, 0.8, 1.0)}
SLIDE_LENGTHS = {"red_slide": 0.60, "blue_slide": 0.35}
PLACE_S = 0.20                   # where along the blue slide a carried bulb's glass starts at release
#                                  (from the tip; a layout may give its own "place_s")
DROP_CLEARANCE = 0.02            # bulb bottom above the blue floor at release
V_ANGLE = math.radians(12.0)     # the tongue's and the cradle's V: each half rises this much outwards
CRADLE = {"length": 0.10, "height": 0.021}   # hand-over cradle (two-robot layout): V-groove on a block

DOUGHNUT = {"R": 0.045, "r": 0.02, "mass": 0.08, "pose": (0.55, -0.45)}

V_DROP = 0.001                   # the tongue's V bottom lies this much below the channel floor


def floor_point(s, up=0.0, y=0.0):
    """Local slide frame (origin on the table below the tip, +x uphill): point at distance s along
    the floor's top surface, raised by `up` along the floor normal."""
    ca, sa = math.cos(ALPHA), math.sin(ALPHA)
    return (s * ca - up * sa, y, TIP_HEIGHT + s * sa + up * ca)


LAYOUTS = {
    "one_robot": {
        "world": "bulbs_and_slides.world",
        # slide name: (centre-line y, tip x)
        "slides": {"red_slide": (0.20, -0.10), "blue_slide": (-0.20, -0.10)},
        "robots": [{"order": [59, 3, 55, 63, 64, 4, 66, 4, 67, 5, 56, 5], "base": [-0.60, -0.50, TABLE_TOP]}],
        "pedestals": [],
        "cradle": None,
        "safety_distance": 0.0,
        "bulbs_on": {"red_slide": 3, "blue_slide": 1},
    },
    "two_robots": {
        "world": "bulbs_and_slides_two_robots.world",
        # The 3-DoF arms (base yaw, one pitch joint limited to +-120 deg from vertical, roll about
        # the arm) cannot move the gripper along its own axis and point it at most 30 deg below the
        # horizontal; they take a bulb the way the gripper's V-grooves are made for: arm horizontal
        # and in line with the bulb, coming down onto it by the pitch joint. So both stand on floor
        # stands at the table's -x end with their shoulders at the bulbs' height; the red slide's
        # centre-line runs through modrob0's base, the blue one's through modrob1's, and the hand-over
        # cradle (its groove across, along y) lies halfway between them, one arm's length from each.
        "x_robots": -1.10,
        "table": (2.0, 1.6, 0.04),
        "robots": [{"order": [59, 3, 55, 63, 57, 5]}, {"order": [59, 3, 55, 63, 57, 5]}],
        "safety_distance": 0.3,
        # modrob1 reaches the release point with its arm about horizontal at the bulbs' height, so
        # anything on the blue slide between its shoulder and that point lies under its long tube: a
        # bulb waiting at the tip would lie 45 mm deep inside it (modrob_motion's
        # test_bas_two_robots_clearance.py). So no bulb waits there, and modrob1 sets the bulb down
        # where it comes to rest, socket first (the hand-over turns it) against the stop post, instead
        # of releasing it uphill to slide under its own arm (where it stuck at the tongue's start).
        "bulbs_on": {"red_slide": 3, "blue_slide": 0},
        "place_s": BULB_GAP + BULB_SOCKET_L + 0.02,
    },
}
# The 3-DoF arm [59, 3, 55, 63, 57, 5] + gripper, from Modules.csv and gripper.xacro: the pitch joint
# (63) is 0.44 m above the base's bottom; the grasp centre (gripper_tcp) 0.64 m from that axis.
ARM3_SHOULDER = 0.10 + 0.10 + 0.14 + 0.10
ARM3_REACH = 0.10 + 0.12 + 0.30 + 0.12


def v_axis_height():
    """Height of a resting bulb's axis above the V's bottom line."""
    return BULB_GLASS_R / math.cos(V_ANGLE)


def _resolve_layouts():
    """Two-robot layout: shoulders at the red tip bulb's height; slides, cradle and bases in line."""
    lay = LAYOUTS["two_robots"]
    xr = lay["x_robots"]
    grasp_s = BULB_GAP + BULB_GLASS_L / 2
    x_pick, _, z_pick = floor_point(grasp_s, v_axis_height() - V_DROP)
    z_pick += TABLE_TOP
    base_z = z_pick - ARM3_SHOULDER
    y_red, y_blue = -ARM3_REACH, ARM3_REACH
    place_s = lay.get("place_s", PLACE_S)
    z_drop = TABLE_TOP + floor_point(place_s + BULB_GLASS_L / 2, BULB_GLASS_R + DROP_CLEARANCE)[2]
    r_drop = math.sqrt(ARM3_REACH ** 2 - (z_drop - z_pick) ** 2)
    x_drop = floor_point(place_s + BULB_GLASS_L / 2, BULB_GLASS_R + DROP_CLEARANCE)[0]
    lay["slides"] = {"red_slide": (y_red, xr + ARM3_REACH - x_pick),
                     "blue_slide": (y_blue, xr + r_drop - x_drop)}
    lay["robots"][0]["base"] = [xr, y_red, base_z]
    lay["robots"][1]["base"] = [xr, y_blue, base_z]
    lay["pedestals"] = [{"xy": [xr, y_red], "height": base_z, "z0": 0.0},
                        {"xy": [xr, y_blue], "height": base_z, "z0": 0.0}]
    lay["cradle"] = {"x": xr, "y": 0.0, "z0": 0.0, "height": z_pick - v_axis_height(),
                     "yaw": math.pi / 2}


_resolve_layouts()


def f(x):
    s = "%.6f" % x
    s = s.rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def pose(x, y, z, r=0.0, p=0.0, yw=0.0):
    return "<pose>%s</pose>" % " ".join(f(v) for v in (x, y, z, r, p, yw))


def box(size):
    return "<box><size>%s</size></box>" % " ".join(f(v) for v in size)


def cyl(r, length):
    return "<cylinder><radius>%s</radius><length>%s</length></cylinder>" % (f(r), f(length))


def material(rgba):
    c = " ".join(f(v) for v in rgba)
    return "<material><ambient>%s</ambient><diffuse>%s</diffuse></material>" % (c, c)


def friction(mu, kd=1):
    return ("<surface><friction><ode><mu>%s</mu><mu2>%s</mu2></ode></friction>"
            "<contact><ode><kp>100000</kp><kd>%s</kd><min_depth>0.001</min_depth></ode></contact></surface>"
            % (f(mu), f(mu), f(kd)))


def part(name, geometry, p, rgba, mu=None, collide=True):
    out = []
    if collide:
        out.append("<collision name='%s_collision'>%s<geometry>%s</geometry>%s</collision>"
                   % (name, p, geometry, friction(mu) if mu is not None else ""))
    out.append("<visual name='%s_visual'>%s<geometry>%s</geometry>%s</visual>"
               % (name, p, geometry, material(rgba)))
    return "\n        ".join(out)


# ----------------------------------------------------------------------------------------- slides


def v_strips(prefix, length, centre, rgba, mu, incline):
    """Two strips forming a shallow V (each rising outwards at V_ANGLE) of total width TONGUE_W, whose
    bottom line runs along the local x axis through `centre` (local frame; pitched by -incline)."""
    out = []
    half = TONGUE_W / 2
    ca, sa = math.cos(incline), math.sin(incline)
    for side, sign in (("left", 1), ("right", -1)):
        # strip centre in the inclined frame (x along, z normal): middle of the strip's top face,
        # moved half a thickness down along the strip's own normal
        yc = sign * half / 2 * math.cos(V_ANGLE)
        zc = half / 2 * math.sin(V_ANGLE)
        yn = -sign * math.sin(V_ANGLE) * (-FLOOR_T / 2)
        zn = math.cos(V_ANGLE) * (-FLOOR_T / 2)
        ly, lz = yc + yn, zc + zn
        x = centre[0] - lz * sa
        z = centre[2] + lz * ca
        out.append(part("%s_%s" % (prefix, side), box((length, half, FLOOR_T)),
                        pose(x, centre[1] + ly, z, sign * V_ANGLE, -incline), rgba, mu))
    return out


def slide_parts(name, rgba, length):
    parts = []
    pitch = -ALPHA
    # tongue: a shallow V (no rails) whose bottom line lies V_DROP below the channel floor
    parts += v_strips("tongue", TONGUE_LEN, floor_point(TONGUE_LEN / 2, -V_DROP), rgba, SLIDE_MU, ALPHA)
    ch_len = length - TONGUE_LEN
    x, _, z = floor_point(TONGUE_LEN + ch_len / 2, -FLOOR_T / 2)
    parts.append(part("floor", box((ch_len, CHANNEL_W + 2 * RAIL_T, FLOOR_T)), pose(x, 0, z, 0, pitch), rgba,
                      SLIDE_MU))
    for side, sign in (("left", 1), ("right", -1)):
        x, _, z = floor_point(TONGUE_LEN + ch_len / 2, RAIL_H / 2)
        y = sign * (CHANNEL_W / 2 + RAIL_T / 2)
        parts.append(part("rail_" + side, box((ch_len, RAIL_T, RAIL_H)), pose(x, y, z, 0, pitch), rgba,
                          SLIDE_MU))
    # stop post at the tip (its uphill face at s = 0)
    x, _, z = floor_point(-POST[0] / 2, POST[2] / 2 - FLOOR_T / 2)
    parts.append(part("stop", box((POST[0], POST[1], POST[2] + FLOOR_T)), pose(x, 0, z, 0, pitch),
                      (0.2, 0.2, 0.2, 1), SLIDE_MU))
    # legs: a thin one under the tongue, a wide one under the high end
    grey = (0.3, 0.3, 0.3, 1)
    xt, _, zt = floor_point(0.03, -FLOOR_T - V_DROP)
    parts.append(part("leg_tip", box((0.02, 0.01, zt)), pose(xt, 0, zt / 2), grey))
    xh, _, zh = floor_point(length - 0.03, -FLOOR_T)
    parts.append(part("leg_high", box((0.04, CHANNEL_W + 2 * RAIL_T, zh)), pose(xh, 0, zh / 2), grey))
    return parts


def slide_model(name, rgba, length, with_pose=None):
    body = "\n        ".join(slide_parts(name, rgba, length))
    return """<model name='%s'>
    <static>true</static>%s
    <link name='link'>
        %s
    </link>
  </model>""" % (name, ("\n    " + with_pose) if with_pose else "", body)


# ----------------------------------------------------------------------------------------- bulb
def bulb_inertial():
    """Mass properties of the two cylinders about the bulb frame (origin: centre of the glass
    cylinder's front face, +x along the axis towards the socket)."""
    m1, m2 = BULB_GLASS_M, BULB_SOCKET_M
    x1, x2 = BULB_GLASS_L / 2, BULB_GLASS_L + BULB_SOCKET_L / 2
    m = m1 + m2
    cx = (m1 * x1 + m2 * x2) / m
    ixx = 0.5 * m1 * BULB_GLASS_R ** 2 + 0.5 * m2 * BULB_SOCKET_R ** 2
    iyy = (m1 * (3 * BULB_GLASS_R ** 2 + BULB_GLASS_L ** 2) / 12 + m1 * (x1 - cx) ** 2
           + m2 * (3 * BULB_SOCKET_R ** 2 + BULB_SOCKET_L ** 2) / 12 + m2 * (x2 - cx) ** 2)
    return m, cx, ixx, iyy


def bulb_model(name, with_pose=None):
    m, cx, ixx, iyy = bulb_inertial()
    glass = (1.0, 0.97, 0.8, 0.6)
    metal = (0.7, 0.7, 0.65, 1.0)
    along_x = (0, math.pi / 2, 0)
    body = [
        "<inertial><pose>%s 0 0 0 0 0</pose><mass>%s</mass><inertia><ixx>%s</ixx><ixy>0</ixy><ixz>0</ixz>"
        "<iyy>%s</iyy><iyz>0</iyz><izz>%s</izz></inertia></inertial>"
        % (f(cx), f(m), "%.3e" % ixx, "%.3e" % iyy, "%.3e" % iyy),
        "<collision name='glass_collision'>%s<geometry>%s</geometry>%s</collision>"
        % (pose(BULB_GLASS_L / 2, 0, 0, *along_x), cyl(BULB_GLASS_R, BULB_GLASS_L), friction(BULB_MU)),
        "<collision name='socket_collision'>%s<geometry>%s</geometry>%s</collision>"
        % (pose(BULB_GLASS_L + BULB_SOCKET_L / 2, 0, 0, *along_x), cyl(BULB_SOCKET_R, BULB_SOCKET_L),
           friction(BULB_MU)),
        # visual: a glass sphere, a neck and the E27 thread
        "<visual name='glass_visual'>%s<geometry><sphere><radius>%s</radius></sphere></geometry>%s</visual>"
        % (pose(BULB_GLASS_R, 0, 0), f(BULB_GLASS_R), material(glass)),
        "<visual name='neck_visual'>%s<geometry>%s</geometry>%s</visual>"
        % (pose(BULB_GLASS_L - 0.005, 0, 0, *along_x), cyl(0.019, 0.02), material(glass)),
        "<visual name='socket_visual'>%s<geometry>%s</geometry>%s</visual>"
        % (pose(BULB_GLASS_L + BULB_SOCKET_L / 2, 0, 0, *along_x), cyl(BULB_SOCKET_R, BULB_SOCKET_L),
           material(metal)),
    ]
    return """<model name='%s'>%s
    <link name='link'>
        %s
    </link>
  </model>""" % (name, ("\n    " + with_pose) if with_pose else "", "\n        ".join(body))


def bulb_pose_on(layout, slide, s_front):
    """World pose (x, y, z, roll, pitch, yaw) of a bulb lying in `slide` of `layout` with its glass front
    face at distance s_front from the tip (on the V tongue when it starts there, else on the floor)."""
    y, tip_x = LAYOUTS[layout]["slides"][slide]
    up = v_axis_height() - V_DROP if s_front < TONGUE_LEN - 0.02 else BULB_GLASS_R
    x, _, z = floor_point(s_front, up)
    return (tip_x + x, y, TABLE_TOP + z, 0.0, -ALPHA, 0.0)


def bulb_length():
    return BULB_GLASS_L + BULB_SOCKET_L


# ----------------------------------------------------------------------------------------- doughnut
def torus_obj(R, r, nu=36, nv=18):
    lines = ["# torus R=%s r=%s (metres), generated by generate_bulbs_and_slides.py" % (R, r)]
    for i in range(nu):
        u = 2 * math.pi * i / nu
        for j in range(nv):
            v = 2 * math.pi * j / nv
            lines.append("v %.6f %.6f %.6f" % ((R + r * math.cos(v)) * math.cos(u),
                                               (R + r * math.cos(v)) * math.sin(u), r * math.sin(v)))
    for i in range(nu):
        for j in range(nv):
            a = i * nv + j + 1
            b = ((i + 1) % nu) * nv + j + 1
            c = ((i + 1) % nu) * nv + (j + 1) % nv + 1
            d = i * nv + (j + 1) % nv + 1
            lines.append("f %d %d %d" % (a, b, c))
            lines.append("f %d %d %d" % (a, c, d))
    return "\n".join(lines) + "\n"


# The doughnut's contact damping. Lying on the table (kp 1e5 in series with its own: 5e4 N/m, kd
# summed, as Gazebo) with kd 1 its contacts are nearly undamped (damping ratio 0.01 for 80 g): the
# torus rocked between mesh triangles at 0.01-0.025 rad/s for ever, just above the auto-disable
# threshold (0.01 rad/s), and its mesh-versus-box collision (1296 triangles) then cost ~0.3 ms
# every step, most of the world's physics. With kd 100 (pair damping ratio 0.8) it comes to rest
# and sleeps within 0.2 s; a touch wakes it as any sleeping body.
DOUGHNUT_KD = 100


def doughnut_model(with_pose=None):
    R, r, m = DOUGHNUT["R"], DOUGHNUT["r"], DOUGHNUT["mass"]
    izz = m * (R ** 2 + 0.75 * r ** 2)
    ixx = m * (0.5 * R ** 2 + 0.625 * r ** 2)
    mesh = ("<mesh><uri>package://modrob_description/models/doughnut/meshes/doughnut.obj</uri>"
            "<scale>1 1 1</scale></mesh>")
    return """<model name='doughnut'>%s
    <link name='link'>
        <inertial><mass>%s</mass><inertia><ixx>%s</ixx><ixy>0</ixy><ixz>0</ixz><iyy>%s</iyy><iyz>0</iyz>
          <izz>%s</izz></inertia></inertial>
        <collision name='collision'><geometry>%s</geometry>%s</collision>
        <visual name='visual'><geometry>%s</geometry>%s</visual>
    </link>
  </model>""" % (("\n    " + with_pose) if with_pose else "", f(m), "%.3e" % ixx, "%.3e" % ixx, "%.3e" % izz,
                 mesh, friction(0.9, DOUGHNUT_KD), mesh, material((0.85, 0.55, 0.3, 1.0)))


# ----------------------------------------------------------------------------------------- world
def table_model(size=TABLE_SIZE):
    lx, ly, t = size
    wood = (0.6, 0.45, 0.3, 1.0)
    parts = [part("top", box((lx, ly, t)), pose(0, 0, TABLE_TOP - t / 2), wood, 0.6)]
    leg_h = TABLE_TOP - t
    for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        leg_pose = pose(sx * (lx / 2 - 0.06), sy * (ly / 2 - 0.06), leg_h / 2)
        parts.append(part("leg%d" % i, box((0.06, 0.06, leg_h)), leg_pose, (0.3, 0.3, 0.3, 1), 0.6))
    return """<model name='table'>
    <static>true</static>
    <pose>0 0 0 0 0 0</pose>
    <link name='link'>
        %s
    </link>
  </model>""" % "\n        ".join(parts)


def pedestal_model(i, ped):
    x, y = ped["xy"]
    h = ped["height"]
    z0 = ped.get("z0", TABLE_TOP)
    return """<model name='pedestal%d'>
    <static>true</static>
    %s
    <link name='link'>
        %s
    </link>
  </model>""" % (i, pose(x, y, z0),
                 part("block", box((0.2, 0.2, h)), pose(0, 0, h / 2), (0.35, 0.35, 0.38, 1), 0.8))


def cradle_model(cradle):
    """Hand-over cradle: a narrow block with a V on top; a bulb laid in it lies along x."""
    h = cradle["height"]
    grey = (0.5, 0.5, 0.55, 1)
    parts = [part("block", box((CRADLE["length"], 0.012, h - FLOOR_T)), pose(0, 0, (h - FLOOR_T) / 2),
                  grey, 0.6)]
    parts += v_strips("v", CRADLE["length"], (0.0, 0.0, h), grey, 0.6, 0.0)
    return """<model name='cradle'>
    <static>true</static>
    %s
    <link name='link'>
        %s
    </link>
  </model>""" % (pose(cradle["x"], cradle["y"], cradle.get("z0", TABLE_TOP), 0, 0,
                      cradle.get("yaw", 0.0)), "\n        ".join(parts))


def world(layout_name):
    layout = LAYOUTS[layout_name]
    models = [table_model(layout.get("table", TABLE_SIZE))]
    for name, (y, tip_x) in layout["slides"].items():
        models.append(slide_model(name, SLIDE_COLOURS[name], SLIDE_LENGTHS[name], pose(tip_x, y, TABLE_TOP)))
    k = 0
    for slide, count in layout["bulbs_on"].items():
        for i in range(count):
            s_front = i * (bulb_length() + BULB_GAP) + BULB_GAP
            models.append(bulb_model("bulb_%d" % k, pose(*bulb_pose_on(layout_name, slide, s_front))))
            k += 1
    dx, dy = DOUGHNUT["pose"]
    models.append(doughnut_model(pose(dx, dy, TABLE_TOP + DOUGHNUT["r"] + 0.001)))
    for i, ped in enumerate(layout["pedestals"]):
        models.append(pedestal_model(i, ped))
    if layout.get("cradle"):
        models.append(cradle_model(layout["cradle"]))
    robots = ", ".join("%s at (%s)" % (r["order"], ", ".join(f(v) for v in r["base"]))
                       for r in layout["robots"])
    return """<?xml version="1.0"?>
<!-- Bulbs and Slides, %s layout (seed 000, appendix). Generated by
     modrob_description/worlds/generate_bulbs_and_slides.py: do not edit, regenerate.
     Robots (spawned by modrob_motion's bulbs_and_slides.launch, not part of this file): %s. -->
<sdf version="1.6">
<world name="bulbs_and_slides">
  <include><uri>model://ground_plane</uri></include>
  <include><uri>model://sun</uri></include>
  <physics type="ode">
    <max_step_size>0.001</max_step_size>
    <real_time_factor>1</real_time_factor>
    <real_time_update_rate>1000</real_time_update_rate>
  </physics>
  %s
</world>
</sdf>
""" % (layout_name.replace("_", " "), robots, "\n  ".join(models))


def model_files(name, text, description):
    d = os.path.join(PKG, "models", name)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "model.sdf"), "w") as fh:
        fh.write('<?xml version="1.0"?>\n'
                 '<!-- generated by modrob_description/worlds/generate_bulbs_and_slides.py -->\n'
                 '<sdf version="1.6">\n  %s\n</sdf>\n' % text)
    with open(os.path.join(d, "model.config"), "w") as fh:
        fh.write("""<?xml version="1.0"?>
<model>
  <name>%s</name>
  <version>1.0</version>
  <sdf version="1.6">model.sdf</sdf>
  <author><name>modrob team</name></author>
  <description>%s</description>
</model>
""" % (name, description))


def _v3(v):
    return "[%s]" % ", ".join(f(x) for x in v)


def layout_yaml():
    ca, sa = math.cos(ALPHA), math.sin(ALPHA)
    lines = ["# Bulbs and Slides layout: generated by",
             "# modrob_description/worlds/generate_bulbs_and_slides.py.",
             "# Do not edit: change the generator and rerun it. Metres, radians, world frame.",
             "table_top: %s" % f(TABLE_TOP),
             "slide_incline: %s" % f(ALPHA),
             "slide_uphill: [%s, 0, %s]   # unit vector up the slides (a resting bulb's +x axis)"
             % (f(ca), f(sa)),
             "bulb:",
             "  glass_radius: %s" % f(BULB_GLASS_R),
             "  glass_length: %s" % f(BULB_GLASS_L),
             "  socket_radius: %s" % f(BULB_SOCKET_R),
             "  socket_length: %s" % f(BULB_SOCKET_L),
             "  mass: %s" % f(BULB_GLASS_M + BULB_SOCKET_M),
             "  grasp_offset: %s   # glass centre along the bulb's +x from its frame origin"
             % f(BULB_GLASS_L / 2),
             "layouts:"]
    for name, lay in LAYOUTS.items():
        lines += ["  %s:" % name, "    world: %s" % lay["world"],
                  "    safety_distance: %s" % f(lay["safety_distance"]), "    bulbs_on:"]
        k = 0
        for slide, count in lay["bulbs_on"].items():
            for i in range(count):
                lines.append("      bulb_%d: %s" % (k, slide))
                k += 1
        lines.append("    robots:")
        for r in lay["robots"]:
            order = ", ".join(str(i) for i in r["order"])
            lines.append("      - {order: [%s], base: %s}" % (order, _v3(r["base"])))
        lines.append("    slides:")
        for sname, (y, tip_x) in lay["slides"].items():
            length = SLIDE_LENGTHS[sname]
            x0, _, z0 = floor_point(0.0)
            xe, _, ze = floor_point(length)
            lines += ["      %s:" % sname,
                      "        tip: %s      # channel floor level at the stop post"
                      % _v3((tip_x + x0, y, TABLE_TOP + z0)),
                      "        high_end: %s" % _v3((tip_x + xe, y, TABLE_TOP + ze)),
                      "        half_width: %s" % f(CHANNEL_W / 2),
                      "        length: %s" % f(length)]
        by, btx = lay["slides"]["blue_slide"]
        px, _, pz = floor_point(lay.get("place_s", PLACE_S) + BULB_GLASS_L / 2, BULB_GLASS_R + DROP_CLEARANCE)
        lines.append("    place_point: %s   # glass centre at release, over the blue slide"
                     % _v3((btx + px, by, TABLE_TOP + pz)))
        if lay.get("cradle"):
            c = lay["cradle"]
            lines.append("    cradle_point: %s   # glass centre of a bulb lying in the cradle"
                         % _v3((c["x"], c["y"], c.get("z0", TABLE_TOP) + c["height"] + v_axis_height())))
            yaw = c.get("yaw", 0.0)
            lines.append("    cradle_axis: %s" % _v3((math.cos(yaw), math.sin(yaw), 0.0)))
    return "\n".join(lines) + "\n"


def main():
    for name in LAYOUTS:
        with open(os.path.join(HERE, LAYOUTS[name]["world"]), "w") as fh:
            fh.write(world(name))
    with open(os.path.join(HERE, "bulbs_and_slides_layout.yaml"), "w") as fh:
        fh.write(layout_yaml())
    model_files("bulb", bulb_model("bulb"), "A60 light bulb lying on its side: collision = glass and E27 "
                "socket cylinders; frame at the glass end face, +x towards the socket.")
    for name, length in SLIDE_LENGTHS.items():
        text = ("Bulbs and Slides %s (%.2f m, %.0f deg): frame on the table below the tip, +x uphill."
                % (name.replace("_", " "), length, math.degrees(ALPHA)))
        model_files(name, slide_model(name, SLIDE_COLOURS[name], length), text)
    model_files("doughnut", doughnut_model(), "A doughnut (torus R %.3f m, r %.3f m) as an OBJ mesh."
                % (DOUGHNUT["R"], DOUGHNUT["r"]))
    mesh_dir = os.path.join(PKG, "models", "doughnut", "meshes")
    os.makedirs(mesh_dir, exist_ok=True)
    with open(os.path.join(mesh_dir, "doughnut.obj"), "w") as fh:
        fh.write(torus_obj(DOUGHNUT["R"], DOUGHNUT["r"]))
    print("wrote worlds and models under %s" % PKG)


if __name__ == "__main__":
    main()

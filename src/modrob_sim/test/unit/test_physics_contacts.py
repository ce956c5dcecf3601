"""Tier 1: contacts of the physics core: friction on a ramp, meshes, SDF worlds, collision
filtering inside a model."""
import importlib.util
import logging
import math
import os
import random

import pytest

from modrob_sim.errors import ModelError
from modrob_sim.physics import World

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "physics")
_spec = importlib.util.spec_from_file_location("physics_helpers", os.path.join(_FIX, "physics_helpers.py"))
H = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(H)


def box_on_ramp(angle, mu, native=None, yaw=0.0):
    world = World(native=native)
    world.add_urdf("ramp", H.ramp(angle, mu))
    box = H.robot("box", H.box_link("box", 1.0, (0.2, 0.2, 0.1), mu))
    # resting on the slope: rotated with it, centre 0.05 m above the surface
    n = (math.sin(angle), 0.0, math.cos(angle))
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    qp = (0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2))
    # pitch (slope) then yaw about the slope normal
    from modrob_sim.physics.transforms import quat_from_axis_angle, quat_mul
    q = quat_mul(quat_from_axis_angle(n, yaw), qp)
    del cy, sy
    model = world.add_urdf("box", box, pose=((0.0501 * n[0], 0.0, 0.0501 * n[2]), q))
    return world, model


@pytest.mark.parametrize("yaw", [0.0, 0.6])
def test_box_with_mu_07_stays_on_a_30_degree_ramp(yaw):
    world, box = box_on_ramp(math.radians(30), 0.7, yaw=yaw)
    start = box.pose[0]
    world.step(2000)
    end = box.pose[0]
    assert math.dist(start, end) < 0.005
    assert world.pop_events() == []


@pytest.mark.parametrize("yaw", [0.0, 0.6])
def test_box_with_mu_07_slides_down_a_40_degree_ramp(yaw):
    angle = math.radians(40)
    world, box = box_on_ramp(angle, 0.7, yaw=yaw)
    start = box.pose[0]
    world.step(1000)
    end = box.pose[0]
    travelled = math.dist(start, end)
    # a = g (sin - mu cos) = 1.05 m/s^2 -> 0.53 m in 1 s
    expected = 0.5 * 9.81 * (math.sin(angle) - 0.7 * math.cos(angle)) * 1.0 ** 2
    assert travelled == pytest.approx(expected, rel=0.15)
    assert end[2] < start[2]


def test_ramp_on_the_python_path_too():
    world, box = box_on_ramp(math.radians(40), 0.7, native=False)
    z0 = box.pose[0][2]
    world.step(500)
    assert box.pose[0][2] < z0 - 0.05
    world, box = box_on_ramp(math.radians(30), 0.7, native=False)
    p0 = box.pose[0]
    world.step(500)
    assert math.dist(p0, box.pose[0]) < 0.005


def mesh_urdf(filename, scale="1 1 1"):
    return H.robot("m", '<link name="m">%s<collision><geometry><mesh filename="%s" scale="%s"/>'
                   '</geometry></collision></link>' % (H.inertial(0.5, 8e-4, 8e-4, 8e-4), filename, scale))


@pytest.mark.parametrize("name", ["cube_binary.stl", "cube_ascii.stl", "cube.obj", "cube.dae"])
def test_mesh_cube_rests_on_the_ground(name):
    world = World()
    world.add_sdf(H.fixture("table_world.sdf").split("<model name=\"table\">")[0] + "</world></sdf>")
    m = world.add_urdf("cube", mesh_urdf("file://" + os.path.join(_FIX, name)),
                       pose=((0.0, 0.0, 0.3), (0.0, 0.0, 0.0, 1.0)))
    world.step(1500)
    assert m.pose[0][2] == pytest.approx(0.05, abs=0.002)
    assert world.pop_events() == []


@pytest.mark.parametrize("native,name", [(None, "cube.obj"), (None, "box"), (False, "box")])
def test_a_link_whose_collisions_are_off_falls_through_and_rests_again_when_on(native, name):
    # Link.set_collides (the grasp fix's disable_collisions_on_attach): a triangle mesh (the C
    # loop's own geom) and a primitive; off: no contact, it falls; on again: it rests again
    world = World(native=native)
    world.add_sdf(H.fixture("table_world.sdf").split("<model name=\"table\">")[0] + "</world></sdf>")
    urdf = mesh_urdf("file://" + os.path.join(_FIX, name)) if name != "box" else \
        H.robot("m", H.box_link("m", 0.5, (0.1, 0.1, 0.1)))
    m = world.add_urdf("cube", urdf, pose=((0.0, 0.0, 0.3), (0.0, 0.0, 0.0, 1.0)))
    link = m.links["m"]
    world.step(800)
    assert m.pose[0][2] == pytest.approx(0.05, abs=0.002) and link.collides
    link.set_collides(False)
    world.step(100)
    assert not link.collides and m.pose[0][2] < 0.0
    assert not [c for c in world.contacts() if "cube" in (c[0], c[2])]
    link.set_collides(True)
    m.set_pose(((0.0, 0.0, 0.3), (0.0, 0.0, 0.0, 1.0)))
    world.step(800)
    assert m.pose[0][2] == pytest.approx(0.05, abs=0.002)


def test_mesh_scale_and_resolver():
    calls = []

    def resolver(uri):
        calls.append(uri)
        assert uri == "package://fake_pkg/meshes/cube.obj"
        return os.path.join(_FIX, "cube.obj")

    world = World(resource_resolver=resolver)
    world.add_sdf(H.fixture("table_world.sdf").split("<model name=\"table\">")[0] + "</world></sdf>")
    m = world.add_urdf("cube", mesh_urdf("package://fake_pkg/meshes/cube.obj", "2 2 3"),
                       pose=((0.0, 0.0, 0.5), (0.0, 0.0, 0.0, 1.0)))
    world.step(1500)
    assert calls
    assert m.pose[0][2] == pytest.approx(0.15, abs=0.002)  # 0.1 m cube scaled 3x in z


def test_sdf_world_with_ground_plane_static_table_and_can():
    world = World()
    models = world.add_sdf(H.fixture("table_world.sdf"))
    assert [m.name for m in models] == ["ground_plane", "table", "can"]
    assert world.models["table"].is_static and world.models["ground_plane"].is_static
    assert models[2].kind == "sdf"
    world.step(1000)
    can = world.models["can"]
    assert can.pose[0] == pytest.approx((1.0, 0.1, 0.75 + 0.06), abs=0.002)
    assert world.models["table"].links["top"].pose[0] == pytest.approx((1.0, 0.0, 0.725))


def test_links_of_one_model_do_not_collide_unless_self_collide():
    # a free link of the model above the model's own (world-fixed) table
    def model(self_collide):
        gz = ('<gazebo reference="b"><selfCollide>true</selfCollide></gazebo>' if self_collide else "")
        return H.robot("a", '<link name="world"/>' + H.box_link("a", 1.0, (0.3, 0.3, 0.1)) +
                       '<joint name="fix" type="fixed"><parent link="world"/><child link="a"/>'
                       '<origin xyz="0 0 1"/></joint>' + H.box_link("b", 1.0, (0.1, 0.1, 0.1)) +
                       H.joint("free", "floating", "a", "b", "0 0 0.3") + gz)
    results = {}
    for sc in (False, True):
        world = World()
        m = world.add_urdf("a", model(sc))
        world.step(1000)
        results[sc] = m.links["b"].pose[0][2]
        assert world.pop_events() == []
    # without selfCollide "b" falls through "a" (free fall for 1 s: ~4.9 m)
    assert results[False] < 1.3 - 4.0
    # with it, "b" lands on "a" (top at 1.05): centre at 1.10 (less the 1 mm surface layer)
    assert results[True] == pytest.approx(1.099, abs=0.002)


def test_friction_is_the_smaller_mu_of_the_two_surfaces():
    angle = math.radians(30)
    for box_mu, ramp_mu, slides in ((0.7, 0.3, True), (0.3, 0.7, True), (0.7, 0.7, False)):
        world = World()
        world.add_urdf("ramp", H.ramp(angle, ramp_mu))
        n = (math.sin(angle), 0.0, math.cos(angle))
        box = world.add_urdf("box", H.robot("box", H.box_link("box", 1.0, (0.2, 0.2, 0.1), box_mu)),
                             pose=((0.0501 * n[0], 0.0, 0.0501 * n[2]),
                                   (0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2))))
        p0 = box.pose[0]
        world.step(500)
        assert (math.dist(p0, box.pose[0]) > 0.05) == slides, (box_mu, ramp_mu)


def test_kp_kd_give_a_soft_contact():
    def sink(kp):
        world = World()
        world.add_urdf("ground", H.fixture("ground_box.urdf"))
        body = H.box_link("b", 10.0, (0.2, 0.2, 0.2))
        body += '<gazebo reference="b"><kp>%r</kp><kd>100</kd><maxVel>1</maxVel></gazebo>' % kp
        m = world.add_urdf("b", H.robot("b", body), pose=((0, 0, 0.1), (0, 0, 0, 1)))
        world.step(1500)
        return 0.1 - m.pose[0][2]
    stiff, soft = sink(1e12), sink(1e5)
    assert stiff < 0.0011  # at most the 1 mm contact surface layer
    # kp in series with the ground's (1e12), 4 contact points in parallel: m g / (4 kp) more
    assert soft == pytest.approx(0.001 + 98.1 / (4 * 1e5), abs=5e-5)


def gripper_lift(mu, native=None):
    """Two 3 N force-limited prismatic fingers squeeze a 0.1 kg can and lift it 0.2 m; returns how
    far the can rose. Friction capacity 2 * mu * 3 N against m g = 0.98 N."""
    body = ('<link name="world"/>' + H.box_link("base", 2.0, (0.1, 0.1, 0.05)) +
            H.joint("lift", "prismatic", "world", "base", "0 0 0.5", axis="0 0 1",
                    limit=(-0.5, 0.5, 200.0, 1.0)) +
            H.box_link("fl", 0.05, (0.02, 0.04, 0.12), mu, "0 0 -0.06") +
            H.box_link("fr", 0.05, (0.02, 0.04, 0.12), mu, "0 0 -0.06") +
            H.joint("jl", "prismatic", "base", "fl", "0.06 0 -0.025", axis="-1 0 0",
                    limit=(0.0, 0.05, 3.0, 0.5)) +
            H.joint("jr", "prismatic", "base", "fr", "-0.06 0 -0.025", axis="1 0 0",
                    limit=(0.0, 0.05, 3.0, 0.5)))
    can_xml = H.robot("can", '<link name="c">%s<collision><geometry><cylinder radius="0.03" length="0.12"/>'
                      '</geometry></collision></link><gazebo reference="c"><mu1>%r</mu1><mu2>%r</mu2>'
                      '</gazebo>' % (H.inertial(0.1, 1.4e-4, 1.4e-4, 4.5e-5), mu, mu))
    world = World(native=native)
    world.add_urdf("ground", H.fixture("ground_box.urdf"))
    g = world.add_urdf("g", H.robot("g", body))
    can = world.add_urdf("can", can_xml, pose=((0, 0, 0.06), (0, 0, 0, 1)))
    lift, jl, jr = g.joints["lift"], g.joints["jl"], g.joints["jr"]

    def step(target, squeeze):
        lift.set_effort(2000 * (target - lift.position) - 100 * lift.velocity + 2.2 * 9.81)
        if squeeze:
            jl.set_effort(3.0)
            jr.set_effort(3.0)
        world.step()

    for _ in range(1500):
        step(-0.33, False)
    for _ in range(500):
        step(-0.33, True)
    z0 = can.pose[0][2]
    for i in range(3000):
        step(-0.33 + min(0.2, i * 1e-4), True)
    assert world.pop_events() == []
    return can.pose[0][2] - z0


@pytest.mark.parametrize("mu, holds", [(0.2, True), (0.15, False)])
def test_force_limited_grasp_holds_exactly_when_friction_suffices(mu, holds):
    rise = gripper_lift(mu)
    if holds:
        assert rise == pytest.approx(0.2, abs=0.002)
    else:
        assert rise < 0.01


@pytest.mark.parametrize("native", [None, False])
def test_contact_points_of_the_last_step(native):
    world = World(native=native)
    world.add_urdf("ground", H.fixture("ground_box.urdf"))
    world.add_urdf("box", H.fixture("box.urdf"), pose=((0.5, 0, 0.2), (0, 0, 0, 1)))
    world.set_physics_params(auto_disable=False)
    world.step(600)
    cps = world.contacts()
    assert len(cps) == 4
    for c in cps:
        assert {c.model1, c.model2} == {"ground", "box"}
        assert c.position[2] == pytest.approx(0.0, abs=0.002)
        assert abs(c.normal[2]) == pytest.approx(1.0, abs=1e-6)
        assert 0.0 <= c.depth < 0.002
    xs = sorted(c.position[0] for c in cps)
    assert xs[0] == pytest.approx(0.4, abs=1e-3) and xs[-1] == pytest.approx(0.6, abs=1e-3)
    # the contact forces on the resting 2 kg box (ODE's contact joint feedback) carry its weight;
    # the ground is static: nothing is reported on its side
    on_box = [c.force1 if c.model1 == "box" else c.force2 for c in cps]
    assert sum(f[2] for f in on_box) == pytest.approx(2.0 * 9.81, rel=0.01)
    assert all(f[2] >= -1e-9 for f in on_box)                  # a contact only pushes
    assert abs(sum(f[0] for f in on_box)) < 0.01 and abs(sum(f[1] for f in on_box)) < 0.01
    # the static ground gets the reaction, its torque about the ground link's origin
    for c in cps:
        box_first = c.model1 == "box"
        fb, fg, tg = (c.force1, c.force2, c.torque2) if box_first else (c.force2, c.force1, c.torque1)
        assert fg == pytest.approx(tuple(-x for x in fb), abs=1e-12)
        o = world.models["ground"].links["slab"].pose[0]
        r = [p - q for p, q in zip(c.position, o)]
        assert tg == pytest.approx((r[1] * fg[2] - r[2] * fg[1], r[2] * fg[0] - r[0] * fg[2],
                                    r[0] * fg[1] - r[1] * fg[0]), abs=1e-9)
    # about the box's centre (0.05 m above the contacts) the corner forces balance
    torque = [sum((c.torque1 if c.model1 == "box" else c.torque2)[k] for c in cps) for k in range(3)]
    assert max(abs(x) for x in torque) < 0.01


@pytest.mark.parametrize("native", [None, False])
def test_contact_forces_between_two_bodies_are_equal_and_opposite(native):
    world = World(native=native)
    world.add_urdf("ground", H.fixture("ground_box.urdf"))
    world.add_urdf("box", H.fixture("box.urdf"), pose=((0.5, 0, 0.06), (0, 0, 0, 1)))
    world.add_urdf("top", H.robot("top", H.box_link("top", 3.0, (0.1, 0.1, 0.1))),
                   pose=((0.5, 0, 0.16), (0, 0, 0, 1)))
    world.set_physics_params(auto_disable=False)
    world.step(600)
    between = [c for c in world.contacts() if {c.model1, c.model2} == {"box", "top"}]
    assert between
    on_top = [c.force1 if c.model1 == "top" else c.force2 for c in between]
    on_box = [c.force2 if c.model1 == "top" else c.force1 for c in between]
    assert sum(f[2] for f in on_top) == pytest.approx(3.0 * 9.81, rel=0.01)
    for a, b in zip(on_top, on_box):
        assert a == pytest.approx(tuple(-x for x in b), abs=1e-9)
    ground = [c.force1 if c.model1 == "box" else c.force2 for c in world.contacts()
              if {c.model1, c.model2} == {"box", "ground"}]
    assert sum(f[2] for f in ground) == pytest.approx(5.0 * 9.81, rel=0.01)


_SHAPES = ("<box><size>0.1 0.08 0.06</size></box>", "<sphere><radius>0.05</radius></sphere>",
           "<cylinder><radius>0.04</radius><length>0.1</length></cylinder>")


def _scattered(native):
    """Boxes, spheres and cylinders dropped close together over a static table and the ground,
    and an articulated model (its own links do not collide) among them."""
    world = World(native=native)
    world.add_sdf("""<sdf version="1.6"><model name="ground"><static>true</static><link name="l">
        <collision name="c"><geometry><plane><normal>0 0 1</normal></plane></geometry></collision>
        </link></model></sdf>""")
    world.add_sdf("""<sdf version="1.6"><model name="table"><static>true</static><pose>0.5 0 0.2 0 0 0</pose>
        <link name="l"><collision name="c"><geometry><box><size>0.6 0.6 0.05</size></box></geometry>
        </collision></link></model></sdf>""")
    world.add_urdf("arm", H.fixture("pendulum.urdf"), pose=((0.3, 0.1, 0.3), (0, 0, 0, 1)))
    rnd = random.Random(3)
    for i in range(60):
        pose = (rnd.uniform(-0.4, 1.0), rnd.uniform(-0.4, 0.4), 0.05 + 0.5 * rnd.random(),
                rnd.random(), rnd.random())
        world.add_sdf("""<sdf version="1.6"><model name="b%d"><pose>%f %f %f %f %f 0</pose><link name="l">
            <inertial><mass>0.1</mass></inertial><collision name="c"><geometry>%s</geometry></collision>
            </link></model></sdf>""" % ((i,) + pose + (_SHAPES[i % 3],)))
    return world


def test_the_c_loops_broadphase_finds_the_pairs_odes_spaces_find():
    # the C loop sorts and sweeps the geoms' boxes itself (mr_sweep); the pure-Python path asks
    # ODE's hash spaces (dSpaceCollide, dSpaceCollide2). From the same poses both make the same
    # contacts: the same pairs, points and depths
    def made(native):
        world = _scattered(native)
        world.step(1)
        return world, sorted((tuple(sorted([(c.model1, c.link1), (c.model2, c.link2)])),
                              tuple(round(x, 9) for x in c.position), round(c.depth, 12))
                             for c in world.contacts())
    native, ours = made(None)
    assert native.native
    pure, odes = made(False)
    assert not pure.native
    pairs = {p for p, _, _ in ours}
    assert len(ours) > 20
    assert any(("table", "l") in p for p in pairs)                       # moving - static
    assert any(p[0][0].startswith("b") and p[1][0].startswith("b") for p in pairs)  # moving - moving
    assert ours == odes


def test_spawn_overlap_with_a_mesh_is_warned(caplog):
    world = World()
    world.add_urdf("ground", H.fixture("ground_box.urdf"))
    with caplog.at_level("WARNING", logger="modrob_sim.physics"):
        world.add_urdf("cube", mesh_urdf("file://" + os.path.join(_FIX, "cube.obj")),
                       pose=((0.0, 0.0, 0.02), (0.0, 0.0, 0.0, 1.0)))
    assert any("spawn overlap" in r.getMessage() and "'cube'" in r.getMessage() for r in caplog.records)


@pytest.mark.parametrize("native", [None, False])
@pytest.mark.parametrize("fdir, slides", [("1 0 0", True), ("0 1 0", False)])
def test_fdir1_sets_the_direction_of_mu1(native, fdir, slides):
    """Box with mu1 0.2 along <fdir1>, mu2 1.0 across, on a 30 degree ramp (tan 30 = 0.58):
    it slides when mu1 points down the slope (box x), holds when it points across (box y)."""
    angle = math.radians(30)
    world = World(native=native)
    world.add_urdf("ramp", H.ramp(angle, 1.0))
    link = H.box_link("box", 1.0, (0.2, 0.2, 0.1))
    link += '<gazebo reference="box"><mu1>0.2</mu1><mu2>1.0</mu2><fdir1>%s</fdir1></gazebo>' % fdir
    n = (math.sin(angle), 0.0, math.cos(angle))
    box = world.add_urdf("box", H.robot("box", link),
                         pose=((0.0501 * n[0], 0.0, 0.0501 * n[2]),
                               (0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2))))
    p0 = box.pose[0]
    world.step(500)
    moved = math.dist(p0, box.pose[0])
    if slides:
        # a = g (sin - 0.2 cos) = 3.2 m/s^2 -> 0.4 m in 0.5 s
        assert moved == pytest.approx(0.5 * 9.81 * (math.sin(angle) - 0.2 * math.cos(angle)) * 0.25,
                                      rel=0.15)
    else:
        assert moved < 0.005


GROUND = ('<sdf version="1.6"><world name="w"><include><uri>model://ground_plane</uri></include>'
          '</world></sdf>')


@pytest.mark.parametrize("native", [None, False])
def test_a_spawn_overlap_is_pushed_out_at_once_but_leaves_at_most_maxvel(native):
    """Gazebo's split of contact correction: a box spawned 5 cm deep in the ground is out within
    a few steps (the contact's ERP), yet never moves faster than maxVel plus what gravity adds."""
    world = World(native=native)
    world.add_sdf(GROUND)
    link = H.box_link("box", 1.0, (0.2, 0.2, 0.2)) + \
        '<gazebo reference="box"><kp>1e7</kp><kd>1</kd><maxVel>0.01</maxVel></gazebo>'
    box = world.add_urdf("box", H.robot("box", link), pose=((0.0, 0.0, 0.05), (0.0, 0.0, 0.0, 1.0)))
    for _ in range(20):
        world.step(1)
        assert abs(box.twist[0][2]) < 0.01 + 9.81 * world.time_step + 1e-9
    # at rest: half its height above the ground, less at most the 1 mm surface layer
    assert 0.0985 < box.pose[0][2] < 0.1005
    world.step(200)
    assert 0.0985 < box.pose[0][2] < 0.1005
    assert world.pop_events() == []


@pytest.mark.parametrize("native", [None, False])
@pytest.mark.parametrize("urdf_cap, sdf_cap, expected",
                         [(None, None, 4), (1, None, 1), (None, 2, 2), (3, 2, 2)])
def test_max_contacts_of_a_collision_lowers_the_worlds_cap(native, urdf_cap, sdf_cap, expected):
    """<maxContacts> (URDF) and <collision><max_contacts> (SDF) cap the contacts of every pair the
    collision is in at the smaller of theirs and the world's (4 here)."""
    world = World(native=native)
    sdf_max = "<max_contacts>%d</max_contacts>" % sdf_cap if sdf_cap else ""
    world.add_sdf('<sdf version="1.6"><world name="w"><model name="floor"><static>true</static>'
                  '<link name="l"><collision name="c">%s<geometry><box><size>2 2 0.1</size></box>'
                  '</geometry></collision></link></model></world></sdf>' % sdf_max)
    link = H.box_link("box", 1.0, (0.2, 0.2, 0.2))
    if urdf_cap:
        link += '<gazebo reference="box"><maxContacts>%d</maxContacts></gazebo>' % urdf_cap
    world.add_urdf("box", H.robot("box", link), pose=((0.0, 0.0, 0.1505), (0.0, 0.0, 0.0, 1.0)))
    world.step(50)
    assert len([c for c in world.contacts() if "box" in (c[0], c[2])]) == expected


@pytest.mark.parametrize("native", [None, False])
@pytest.mark.parametrize("ramp_mu1, slides", [(1.0, True), (0.1, False)])
def test_fdir1_on_both_sides_comes_from_the_surface_with_the_smaller_mu1(native, ramp_mu1, slides):
    """Box: mu1 0.2 along its x (down the 30 degree slope), mu2 1.0. Ramp: <fdir1> across the slope.
    Gazebo takes fdir1 of the surface with the smaller mu1: the box's (mu 0.2 down the slope: it
    slides) while the ramp's mu1 is 1.0, the ramp's (min mu1 0.1 across, min mu2 1.0 down the
    slope: it holds) when the ramp's mu1 is 0.1."""
    angle = math.radians(30)
    world = World(native=native)
    ramp = H.ramp(angle, 1.0).replace(
        "<mu1>1.0</mu1><mu2>1.0</mu2>", "<mu1>%r</mu1><mu2>1.0</mu2><fdir1>0 1 0</fdir1>" % ramp_mu1)
    world.add_urdf("ramp", ramp)
    link = H.box_link("box", 1.0, (0.2, 0.2, 0.1))
    link += '<gazebo reference="box"><mu1>0.2</mu1><mu2>1.0</mu2><fdir1>1 0 0</fdir1></gazebo>'
    n = (math.sin(angle), 0.0, math.cos(angle))
    box = world.add_urdf("box", H.robot("box", link),
                         pose=((0.0501 * n[0], 0.0, 0.0501 * n[2]),
                               (0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2))))
    p0 = box.pose[0]
    world.step(500)
    moved = math.dist(p0, box.pose[0])
    assert (moved > 0.2) if slides else (moved < 0.005)


@pytest.mark.parametrize("native", [None, False])
def test_min_depth_of_two_bodies_is_the_smaller(native):
    """Gazebo lets two bodies stay sunk into each other by the SMALLER of their minDepth: a box
    with minDepth 5 mm spawned 8 mm deep into a box with none is pushed out to the surface
    layer (1 mm), not to 5 mm."""
    world = World(native=native)
    world.add_sdf(GROUND)
    lower = world.add_urdf("lower", H.robot("lower", H.box_link("lower", 2.0, (0.4, 0.4, 0.1))),
                           pose=((0.0, 0.0, 0.05), (0.0, 0.0, 0.0, 1.0)))
    link = H.box_link("upper", 1.0, (0.2, 0.2, 0.1)) + \
        '<gazebo reference="upper"><minDepth>0.005</minDepth></gazebo>'
    upper = world.add_urdf("upper", H.robot("upper", link), pose=((0.0, 0.0, 0.142), (0.0, 0.0, 0.0, 1.0)))
    world.step(1000)
    sunk = (lower.pose[0][2] + 0.05) - (upper.pose[0][2] - 0.05)
    assert 0.0005 < sunk < 0.0015


def test_a_missing_collision_mesh_collides_as_the_links_visual_mesh_with_one_warning(caplog):
    """katana_description's collision meshes are convex decompositions its build makes (with
    convex_decomposition, which Debian lacks): from a source checkout they do not exist."""
    cube = "file://" + os.path.join(_FIX, "cube_binary.stl")
    unbuilt = "file://" + os.path.join(_FIX, "convex", "cube_binary_convex.stl")
    xml = H.robot("m", '<link name="m">%s<visual><geometry><mesh filename="%s"/></geometry></visual>'
                  '<collision><geometry><mesh filename="%s"/></geometry></collision></link>'
                  % (H.inertial(0.5, 8e-4, 8e-4, 8e-4), cube, unbuilt))
    world = World()
    world.add_sdf(H.fixture("table_world.sdf").split("<model name=\"table\">")[0] + "</world></sdf>")
    with caplog.at_level(logging.WARNING):
        m = world.add_urdf("cube", xml, pose=((0.0, 0.0, 0.3), (0.0, 0.0, 0.0, 1.0)))
    world.step(1500)
    assert m.pose[0][2] == pytest.approx(0.05, abs=0.002)     # rests on the visual cube
    warnings = [r.getMessage() for r in caplog.records if "collision mesh" in r.getMessage()]
    assert len(warnings) == 1
    assert "model 'cube': 1 collision mesh file does not exist" in warnings[0]
    assert "m ('%s' -> '%s')" % (unbuilt, cube) in warnings[0]
    # without a visual mesh to stand in, the model is refused as before, naming the file
    with pytest.raises(ModelError, match="cube_binary_convex.stl"):
        world.add_urdf("bare", H.robot("bare", '<link name="m">%s<collision><geometry><mesh filename="%s"/>'
                                       '</geometry></collision></link>'
                                       % (H.inertial(0.5, 8e-4, 8e-4, 8e-4), unbuilt)))

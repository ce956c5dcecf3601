"""Tier 1: the physics core's basic physics and contract accessors (pendulum, box drop, hooks)."""
import logging
import math
import os

import pytest

from modrob_sim.physics import World

FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "physics")


def fixture(name):
    with open(os.path.join(FIX, name)) as f:
        return f.read()


def zero_crossings(values, dt):
    """Times of upward zero crossings, linearly interpolated."""
    out = []
    for i in range(1, len(values)):
        a, b = values[i - 1], values[i]
        if a < 0.0 <= b:
            out.append((i - 1 + (-a) / (b - a)) * dt)
    return out


def test_pendulum_small_swing_period_matches_compound_pendulum_theory():
    world = World(time_step=0.001)
    model = world.add_urdf("pendulum", fixture("pendulum.urdf"), joint_positions={"swing": 0.05})
    joint = model.joints["swing"]
    assert joint.position == pytest.approx(0.05, abs=1e-9)
    qs = []
    for _ in range(4000):
        world.step()
        qs.append(joint.position)
    crossings = zero_crossings(qs, world.time_step)
    assert len(crossings) >= 3
    period = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    m, length, ic = 1.0, 0.25, 0.0208667  # fixture: rod mass, pivot-to-COM distance, inertia about COM
    theory = 2.0 * math.pi * math.sqrt((ic + m * length ** 2) / (m * 9.81 * length))
    assert abs(period - theory) / theory < 0.02, (period, theory)
    # amplitude is kept (no numerical damping worth speaking of in 4 s)
    assert max(qs[-1200:]) == pytest.approx(0.05, rel=0.05)


def test_pendulum_link_pose_follows_joint_angle():
    world = World()
    model = world.add_urdf("pendulum", fixture("pendulum.urdf"), joint_positions={"swing": 0.3})
    pos, quat = model.links["rod"].pose
    # link frame at the pivot (z = 1.5), rotated 0.3 rad about y
    assert pos == pytest.approx((0.0, 0.0, 1.5), abs=1e-9)
    assert quat == pytest.approx((0.0, math.sin(0.15), 0.0, math.cos(0.15)), abs=1e-9)
    assert model.links["pivot"].pose[0] == pytest.approx((0.0, 0.0, 1.5))
    assert model.canonical_link.name == "pivot"
    assert set(model.links) == {"pivot", "rod"}
    assert set(model.joints) == {"fix", "swing"}
    j = model.joints["swing"]
    assert (j.type, j.parent, j.child, j.axis) == ("revolute", "pivot", "rod", (0.0, 1.0, 0.0))
    assert (j.lower, j.upper, j.effort_limit, j.velocity_limit) == (-3.0, 3.0, 10.0, 10.0)
    assert model.links["rod"].mass == 1.0


def test_dropped_box_rests_at_half_its_height():
    world = World()
    world.add_urdf("ground", fixture("ground_box.urdf"))
    box = world.add_urdf("box", fixture("box.urdf"), pose=((0.3, -0.2, 0.5), (0, 0, 0, 1)))
    for _ in range(1500):
        world.step()
    (x, y, z), _ = box.pose
    assert z == pytest.approx(0.05, abs=0.002)
    assert (x, y) == pytest.approx((0.3, -0.2), abs=1e-3)
    lin, ang = box.twist
    assert max(abs(v) for v in lin + ang) < 1e-3
    assert world.pop_events() == []


def test_time_and_iterations_and_hooks_get_injected_time():
    world = World(time_step=0.002)
    world.add_urdf("box", fixture("box.urdf"), pose=((0, 0, 1.0), (0, 0, 0, 1)))
    seen = []
    h = world.add_step_hook(before=lambda t, dt: seen.append(("b", t, dt)),
                            after=lambda t, dt: seen.append(("a", t, dt)))
    world.step(3)
    assert world.iterations == 3
    assert world.time == pytest.approx(0.006)
    assert seen[0] == ("b", 0.0, 0.002)
    assert seen[1][0] == "a" and seen[1][1] == pytest.approx(0.002)
    assert [s[0] for s in seen] == ["b", "a"] * 3
    world.remove_step_hook(h)
    world.step()
    assert len(seen) == 6
    with pytest.raises(ValueError):
        world.remove_step_hook(h)


def test_free_fall_matches_g_and_link_twist():
    world = World()
    box = world.add_urdf("box", fixture("box.urdf"), pose=((0, 0, 10.0), (0, 0, 0, 1)))
    world.step(500)
    t = world.time
    assert box.pose[0][2] == pytest.approx(10.0 - 0.5 * 9.81 * t * t, abs=0.01)
    assert box.twist[0][2] == pytest.approx(-9.81 * t, rel=1e-6)


INERTIAL = ('<inertial><mass value="1.0"/>'
            '<inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>')
WELDED = """<robot name="welded">
  <link name="arm">%s<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <joint name="weld" type="fixed"><parent link="arm"/><child link="tip"/><origin xyz="0.2 0 0"/></joint>
  <link name="tip">%%s</link>
  <gazebo reference="arm"><turnGravityOff>true</turnGravityOff></gazebo>
</robot>""" % INERTIAL


@pytest.mark.parametrize("tip, g_share", [("", 0.0), (INERTIAL, 0.5)])
def test_gravity_of_a_welded_body_is_that_of_its_massive_links(tip, g_share):
    """A massless link welded on (a tool frame, gravity on by default) leaves a gravity-off body
    floating, and natively stepped; a massive one with gravity on pulls with its share of g."""
    world = World()
    body = world.add_urdf("welded", WELDED % tip, pose=((0, 0, 10.0), (0, 0, 0, 1)))
    n, dt = 500, world.time_step
    world.step(n)
    # the centre of mass (both links' inertial frames are their link frames; the pull of the tip
    # alone also turns the body)
    links = [body.links["arm"]] + ([body.links["tip"]] if tip else [])
    z = sum(ln.pose[0][2] for ln in links) / len(links)
    # (semi-implicit Euler: after n steps the fall is g dt^2 n (n + 1) / 2)
    assert z == pytest.approx(10.0 - 0.5 * g_share * 9.81 * dt * dt * n * (n + 1), abs=2e-4)
    if world.native and not tip:
        assert world.native_steps == n


def test_gazebo_plugins_are_listed_with_their_namespace():
    xml = fixture("pendulum.urdf").replace("</robot>", """
  <gazebo><plugin name="gazebo_ros_control" filename="libgazebo_ros_control.so">
    <robotNamespace>/pend</robotNamespace></plugin></gazebo>
  <gazebo><plugin name="p3d" filename="libgazebo_ros_p3d.so"><bodyName>rod</bodyName></plugin></gazebo>
  <gazebo reference="rod"><sensor type="camera" name="cam"><update_rate>30</update_rate>
    <plugin name="cam_ctrl" filename="libgazebo_ros_camera.so"><cameraName>c</cameraName></plugin>
  </sensor><mu1>0.4</mu1></gazebo>
</robot>""")
    world = World()
    m = world.add_urdf("pendulum", xml, robot_namespace="/spawned")
    specs = {p.filename: p for p in m.plugins}
    assert set(specs) == {"libgazebo_ros_control.so", "libgazebo_ros_p3d.so", "libgazebo_ros_camera.so"}
    assert specs["libgazebo_ros_control.so"].robot_namespace == "/pend"
    assert specs["libgazebo_ros_p3d.so"].robot_namespace == "/spawned"
    assert specs["libgazebo_ros_p3d.so"].element.findtext("bodyName") == "rod"
    cam = specs["libgazebo_ros_camera.so"]
    assert cam.link == "rod" and cam.sensor.get("name") == "cam"
    assert m.robot_namespace == "/spawned" and m.kind == "urdf" and m.source_xml == xml
    assert m.links["rod"].sensors[0].get("type") == "camera"


def test_add_effort_accumulates_and_set_effort_replaces():
    world = World()
    m = world.add_urdf("pendulum", fixture("pendulum.urdf"))
    j = m.joints["swing"]
    j.add_effort(4.0)
    j.add_effort(4.0)
    world.step()
    assert j.effort == 8.0
    j.add_effort(8.0)
    j.add_effort(8.0)
    world.step()
    assert j.effort == 10.0  # the sum, clamped to the limit
    j.add_effort(3.0)
    j.set_effort(1.0)
    world.step()
    assert j.effort == 1.0


def test_default_resolver_finds_package_uris_through_rospkg():
    xml = ('<robot name="m"><link name="m"><inertial><mass value="0.5"/><inertia ixx="1e-3" ixy="0" '
           'ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial><collision><geometry><mesh '
           'filename="package://modrob_sim/test/fixtures/physics/cube_binary.stl"/></geometry></collision>'
           '</link></robot>')
    world = World()
    world.add_urdf("ground", fixture("ground_box.urdf"))
    m = world.add_urdf("m", xml, pose=((0, 0, 0.2), (0, 0, 0, 1)))
    world.step(800)
    assert m.pose[0][2] == pytest.approx(0.05, abs=0.002)


def test_a_missing_visual_mesh_is_not_drawn_and_said_once(caplog, monkeypatch):
    """turtlebot3_description's waffle_base.stl missing from a checkout: the model loads without
    that visual, one warning names it (RViz, the camera renderer's scene, reported it at every
    update of the scene markers, 30 times a second), and the model's package:// URIs are found
    with one crawl of ROS_PACKAGE_PATH."""
    import rospkg
    from modrob_sim.gazebo_ros.markers import WorldMarkers
    made = []

    class CountedRosPack(rospkg.RosPack):
        def __init__(self, *args, **kwargs):
            made.append(self)
            super(CountedRosPack, self).__init__(*args, **kwargs)
    monkeypatch.setattr(rospkg, "RosPack", CountedRosPack)
    cube = "package://modrob_sim/test/fixtures/physics/cube_binary.stl"
    gone = "package://modrob_sim/test/fixtures/physics/waffle_base.stl"
    lost = "file:///nonexistent/meshes/base.dae"
    inertial = ('<inertial><mass value="0.5"/><inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" '
                'izz="1e-3"/></inertial>')
    mesh = '<visual><geometry><mesh filename="%s"/></geometry></visual>'
    xml = ('<robot name="m"><link name="base">%s%s%s<collision><geometry><mesh filename="%s"/></geometry>'
           '</collision></link><link name="top">%s%s</link><joint name="j" type="fixed"><parent link="base"/>'
           '<child link="top"/></joint></robot>'
           % (inertial, mesh % cube, mesh % gone, cube, inertial, mesh % lost))
    world = World()
    with caplog.at_level(logging.WARNING):
        m = world.add_urdf("m", xml, pose=((0, 0, 0.2), (0, 0, 0, 1)))
    assert [g.uri for g in m.links["base"].visuals] == [cube] and m.links["top"].visuals == []
    said = [r.getMessage() for r in caplog.records if "visual mesh" in r.getMessage()]
    assert said == ["model 'm': 2 visual mesh files not found, not drawn (as Gazebo's client draws nothing "
                    "there): base ('%s'); top ('%s')" % (gone, lost)]
    assert len(made) == 1
    markers = WorldMarkers(world, "all").update(force=True)
    assert [mk.mesh_resource for mk in markers.markers if mk.mesh_resource] == [cube]


def test_zero_and_tiny_inertias_do_not_break_ode():
    xml = fixture("pendulum.urdf").replace(
        '<inertia ixx="0.0208667" ixy="0" ixz="0" iyy="0.0208667" iyz="0" izz="0.0000667"/>',
        '<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>').replace(
        '<mass value="1.0"/>', '<mass value="1e-9"/>')
    xml = xml.replace("</robot>", '<link name="massless"/><joint name="m" type="continuous">'
                      '<parent link="rod"/><child link="massless"/><origin xyz="0 0 -0.5"/>'
                      '<axis xyz="1 0 0"/></joint></robot>')
    world = World()
    m = world.add_urdf("p", xml, joint_positions={"swing": 0.5})
    for _ in range(2000):
        m.joints["swing"].set_effort(0.001)
        world.step()
    for ln in m.links.values():
        assert all(math.isfinite(v) for v in ln.pose[0] + ln.pose[1])


def test_an_sdf_models_own_pose_is_given_in_the_frame_of_the_spawn_pose():
    """gazebo_ros's spawn composes the request's initial pose with the model's <pose>: spawned
    with the identity (spawn_model -sdf without -x/-y/-z) a model stands where its file puts it."""
    sdf = ('<sdf version="1.6"><model name="%s"><static>true</static><pose>1 2 0.5 0 0 %r</pose>'
           '<link name="l"><collision name="c"><geometry><box><size>0.1 0.1 0.1</size></box></geometry>'
           '</collision></link></model></sdf>')
    world = World()
    yaw = math.pi / 2
    at_file = world.add_sdf(sdf % ("a", yaw), pose=((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)))[0]
    assert at_file.pose[0] == pytest.approx((1.0, 2.0, 0.5), abs=1e-9)
    assert at_file.pose[1] == pytest.approx((0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)), abs=1e-9)
    # moved to (10, 0, 0) and turned 90 degrees: the file's (1, 2, 0.5) becomes (10 - 2, 1, 0.5)
    # and the yaws add up
    s = math.sqrt(0.5)
    moved = world.add_sdf(sdf % ("b", yaw), pose=((10.0, 0.0, 0.0), (0.0, 0.0, s, s)))[0]
    assert moved.pose[0] == pytest.approx((8.0, 1.0, 0.5), abs=1e-9)
    assert moved.pose[1] == pytest.approx((0.0, 0.0, 1.0, 0.0), abs=1e-9)
    world.close()

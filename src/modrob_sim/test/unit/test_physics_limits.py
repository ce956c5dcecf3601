"""Tier 1: every magnitude is bounded before it reaches ODE (which aborts the process on absurd
numbers), refusals name model, link/joint, field, value and limit, and a refusal changes nothing.
Regression tests for the models and requests that aborted the simulator (see docs/simulator.md,
"Limits")."""
import importlib.util
import logging
import os

import pytest

from modrob_sim.errors import ModelError
from modrob_sim.physics import World, limits

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "physics")
_spec = importlib.util.spec_from_file_location("physics_helpers", os.path.join(_FIX, "physics_helpers.py"))
H = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(H)

INERTIAL = ("<inertial><mass value='1'/><inertia ixx='0.01' ixy='0' ixz='0' iyy='0.01' iyz='0' izz='0.01'/>"
            "</inertial>")


def signature(world):
    return (list(world.models), world.geom_count, world.gravity, world.time_step, world.state_digest())


def scene():
    """Two movable shapes (ODE's collision space aborts only once two exist) on a ground."""
    world = World()
    world.add_urdf("ground", H.fixture("ground_box.urdf"))
    world.add_urdf("box", H.fixture("box.urdf"), pose=((0, 0, 1), (0, 0, 0, 1)))
    world.add_urdf("box2", H.fixture("box.urdf"), pose=((1, 0, 1), (0, 0, 0, 1)))
    return world


def link(geometry, where="collision", extra=""):
    return "<link name='a'>%s<%s>%s<geometry>%s</geometry></%s></link>" % (INERTIAL, where, extra, geometry,
                                                                           where)


def two_links(joint_xml):
    return ("<robot name='x'><link name='a'>%s</link><link name='b'>%s<collision><geometry>"
            "<box size='0.1 0.1 0.1'/></geometry></collision></link>%s</robot>"
            % (INERTIAL, INERTIAL, joint_xml))


BAD_URDF = [
    # (xml, words the refusal must contain)
    ("<robot name='x'>%s</robot>" % link("<capsule radius='-0.1' length='0.2'/>"),
     ["link 'a'", "<capsule> radius", "-0.1", "1e+06"]),
    ("<robot name='x'>%s</robot>" % link("<capsule radius='-0.1' length='0.2'/>", "visual"),
     ["link 'a'", "<visual>", "<capsule> radius", "-0.1"]),
    ("<robot name='x'>%s</robot>" % link("<box size='1e300 1 1'/>"), ["<box> size x", "1e+300", "1e+06"]),
    ("<robot name='x'>%s</robot>" % link("<cylinder radius='0.1' length='1e300'/>"),
     ["<cylinder> length", "1e+300"]),
    ("<robot name='x'>%s</robot>" % link("<box size='1 1 1'/>", extra="<origin xyz='1e12 0 0'/>"),
     ["<origin xyz>", "1e+12", "1e+06 m"]),
    ("<robot name='x'><link name='a'><inertial><mass value='1'/><inertia ixx='1e300' ixy='0' ixz='0' "
     "iyy='1' iyz='0' izz='1'/></inertial></link></robot>", ["<inertia ixx>", "1e+300", "1e+12"]),
    ("<robot name='x'><link name='a'><inertial><mass value='1e300'/></inertial></link></robot>",
     ["<mass>", "1e+300", "1e+09"]),
    (two_links("<joint name='j' type='continuous'><parent link='a'/><child link='b'/>"
               "<axis xyz='1e300 1e300 0'/></joint>"), ["joint 'j'", "<axis xyz>", "1e+300"]),
    (two_links("<joint name='j' type='continuous'><parent link='a'/><child link='b'/>"
               "<axis xyz='1e-300 0 0'/></joint>"), ["joint 'j'", "<axis xyz>", "zero length"]),
    (two_links("<joint name='j' type='fixed'><parent link='a'/><child link='b'/>"
               "<origin xyz='1e200 0 0'/></joint>"), ["joint 'j'", "<origin xyz>", "1e+200"]),
    (two_links("<joint name='j' type='revolute'><parent link='a'/><child link='b'/>"
               "<origin xyz='0 0 1e12'/><limit lower='-1' upper='1' effort='1' velocity='1'/></joint>"),
     ["joint 'j'", "<origin xyz>", "1e+12"]),
    (two_links("<joint name='j' type='prismatic'><parent link='a'/><child link='b'/>"
               "<limit lower='-1' upper='1' effort='1' velocity='1'/><dynamics damping='1e300'/></joint>"),
     ["joint 'j'", "<dynamics damping>", "1e+300"]),
]


@pytest.mark.parametrize("xml, words", BAD_URDF)
def test_absurd_urdf_numbers_are_refused_naming_field_value_and_limit(xml, words):
    world = scene()
    before = signature(world)
    with pytest.raises(ModelError) as err:
        world.add_urdf("bad", xml)
    msg = str(err.value)
    assert "model 'bad'" in msg
    for w in words:
        assert w in msg, (w, msg)
    assert signature(world) == before
    world.step(20)  # and ODE still runs
    assert world.models["box"].pose[0][2] < 1.0


def test_chained_origins_beyond_the_world_extent_are_refused():
    joints = "".join("<joint name='j%d' type='fixed'><parent link='l%d'/><child link='l%d'/>"
                     "<origin xyz='900000 0 0'/></joint>" % (i, i, i + 1) for i in range(15))
    links = "".join("<link name='l%d'>%s<collision><geometry><sphere radius='0.1'/></geometry></collision>"
                    "</link>" % (i, INERTIAL) for i in range(16))
    world = scene()
    before = signature(world)
    with pytest.raises(ModelError, match="position in the world .* beyond 1e\\+07 m"):
        world.add_urdf("far", "<robot name='far'>%s%s</robot>" % (links, joints))
    assert signature(world) == before


BAD_SDF_MODELS = [
    ("<mesh><uri>file:///nonexistent.stl</uri><scale>0 1 1</scale></mesh>",
     ["<mesh> scale", "(0, 1, 1)"]),
    ("<box><size>1 -1 1</size></box>", ["must be positive"]),
]


@pytest.mark.parametrize("geometry, words", BAD_SDF_MODELS)
def test_sdf_geometry_like_urdf(geometry, words):
    sdf = ("<sdf version='1.6'><model name='m'><link name='l'><visual name='v'><geometry>%s</geometry>"
           "</visual></link></model></sdf>" % geometry)
    world = scene()
    before = signature(world)
    with pytest.raises(ModelError) as err:
        world.add_sdf(sdf)
    for w in words:
        assert w in str(err.value)
    assert signature(world) == before


def test_sdf_axis_that_overflows_is_refused():
    sdf = ("<sdf version='1.6'><model name='m'><link name='a'/><link name='b'/>"
           "<joint name='j' type='revolute'><parent>a</parent><child>b</child>"
           "<axis><xyz>1e300 1e300 0</xyz></axis></joint></model></sdf>")
    with pytest.raises(ModelError, match="joint 'j'.*<axis><xyz>"):
        World().add_sdf(sdf)


@pytest.mark.parametrize("physics, words", [
    ("<gravity>0 0 1e308</gravity>", ["<world><gravity>", "1e+308", "1000 m/s^2"]),
    ("<physics type='ode'><max_step_size>5e-324</max_step_size></physics>", ["<max_step_size>", "1e-06"]),
])
def test_sdf_world_settings_beyond_limits_are_refused_before_anything_changes(physics, words):
    world = scene()
    before = signature(world)
    sdf = ("<sdf version='1.6'><world name='w'>%s<model name='m'><link name='l'/></model></world></sdf>"
           % physics)
    with pytest.raises(ModelError) as err:
        world.add_sdf(sdf)
    for w in words:
        assert w in str(err.value)
    assert signature(world) == before


@pytest.mark.parametrize("pose", [((1e12, 0, 0), (0, 0, 0, 1)), ((9.9e8, 0, 0), (0, 0, 0, 1))])
def test_spawn_and_set_pose_beyond_the_length_limit_are_refused(pose):
    world = scene()
    before = signature(world)
    with pytest.raises(ModelError, match="beyond 1e\\+06 m"):
        world.add_urdf("far", H.fixture("box.urdf"), pose=pose)
    with pytest.raises(ValueError, match="beyond 1e\\+06 m"):
        world.models["box"].set_pose(pose)
    assert signature(world) == before
    world.step(20)


def test_wrench_lever_arm_beyond_the_limit_is_refused_and_nothing_is_queued():
    world = scene()
    ln = world.models["box"].links["box"] if "box" in world.models["box"].links else \
        next(iter(world.models["box"].links.values()))
    with pytest.raises(ValueError, match="reference_point .* beyond 1e\\+06 m"):
        ln.add_wrench((0, 1e9, 0), (0, 0, 0), reference_point=(1e308, 0, 0))
    assert not ln.has_wrenches
    world.step(20)
    assert all(abs(x) < 10 for x in world.models["box"].pose[0])


def _slider(lower=-0.5, upper=0.5):
    return two_links("<joint name='s' type='prismatic'><parent link='a'/><child link='b'/><axis xyz='1 0 0'/>"
                     "<limit lower='%r' upper='%r' effort='10' velocity='1'/></joint>" % (lower, upper))


def test_set_configuration_honours_joint_limits_and_refuses_absurd_positions(caplog):
    world = scene()
    m = world.add_urdf("slider", _slider(), pose=((3, 0, 1), (0, 0, 0, 1)))
    with pytest.raises(ValueError, match="joint 's': position 1e\\+12 is beyond 1e\\+06"):
        m.set_configuration(["s"], [1e12])
    assert m.joints["s"].position == pytest.approx(0.0, abs=1e-9)
    with caplog.at_level(logging.WARNING, logger="modrob_sim.physics"):
        m.set_configuration(["s"], [0.8])
    assert m.joints["s"].position == pytest.approx(0.5, abs=1e-9)
    assert "outside its limits [-0.5, 0.5]" in caplog.text
    world.step(10)


def test_planar_joint_leaves_the_child_free_as_gazebo_does(caplog):
    xml = two_links("<joint name='p' type='planar'><parent link='a'/><child link='b'/>"
                    "<origin xyz='0 0 0.5'/><axis xyz='0 0 1'/></joint>")
    world = World()
    with caplog.at_level(logging.WARNING, logger="modrob_sim.physics"):
        m = world.add_urdf("planar", xml, pose=((0, 0, 2), (0, 0, 0, 1)))
    assert "joint 'p' is planar" in caplog.text
    assert len(m.bodies) == 2
    world.step(200)  # no ground: both fall freely, each on its own
    assert m.links["b"].pose[0][2] < 2.5 - 0.15


def test_limits_are_what_docs_promise():
    assert limits.LENGTH_LIMIT * 8 < 2 ** 31 / 100  # far inside ODE's hash-space integer cells
    assert limits.WORLD_EXTENT * 8 < 2 ** 31 / 10
    doc = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..", "docs",
                            "simulator.md")).read()
    for name in ("LENGTH_LIMIT", "WORLD_EXTENT", "MASS_LIMIT", "INERTIA_LIMIT", "GRAVITY_LIMIT",
                 "MIN_TIME_STEP"):
        assert "%g" % getattr(limits, name) in doc, name


def test_collada_up_axis_is_ignored_as_gazebo_and_rviz_do(tmp_path):
    """A can modelled along z whose file says Y_UP (as many exporters write) stands on z."""
    from modrob_sim.physics import meshes
    cube = os.path.join(_FIX, "cube.dae")
    text = open(cube).read().replace("<up_axis>Z_UP</up_axis>", "<up_axis>Y_UP</up_axis>")
    assert "Y_UP" in text
    path = tmp_path / "y_up.dae"
    path.write_text(text)
    z_up = meshes.bounds(meshes.load_mesh(cube)[0])
    y_up = meshes.bounds(meshes.load_mesh(str(path))[0])
    assert y_up == z_up


@pytest.mark.parametrize("field, value, words", [
    ("gravity", (0, 0, 1e308), "within +-1000 m/s^2"),
    ("time_step", 5e-324, "must be in [1e-06, 0.1] s"),
])
def test_world_gravity_and_time_step_beyond_limits_are_refused(field, value, words):
    world = scene()
    before = signature(world)
    with pytest.raises(ValueError) as err:
        setattr(world, field, value)
    assert words in str(err.value)
    assert signature(world) == before
    world.step(20)


def test_sdf_world_refused_for_a_missing_mesh_leaves_gravity_and_physics_alone():
    world = scene()
    before = signature(world)
    params = world.physics_params
    sdf = ("<sdf version='1.6'><world name='w'><gravity>0 0 -1.62</gravity><physics type='ode'>"
           "<max_step_size>0.002</max_step_size><ode><solver><iters>7</iters></solver></ode></physics>"
           "<model name='m'><link name='l'><collision name='c'><geometry><mesh><uri>file:///no/such.stl</uri>"
           "</mesh></geometry></collision></link></model></world></sdf>")
    with pytest.raises(ModelError, match="no/such.stl"):
        world.add_sdf(sdf)
    assert signature(world) == before
    assert world.physics_params == params


def test_physics_params_refused_for_one_bad_value_change_nothing():
    world = scene()
    params = world.physics_params
    for bad in ({"sor": float("nan"), "iters": 7}, {"erp": 5.0, "iters": 7}, {"iters": 1e12}):
        with pytest.raises(ValueError):
            world.set_physics_params(**bad)
        assert world.physics_params == params


def test_prismatic_mimic_with_an_offset_starts_coupled_and_never_trips_the_guard():
    xml = ("<robot name='x'><link name='a'>%s</link><link name='b'>%s</link><link name='c'>%s</link>"
           "<joint name='m' type='prismatic'><parent link='a'/><child link='b'/><axis xyz='1 0 0'/>"
           "<limit lower='-1' upper='1' effort='10' velocity='1'/></joint>"
           "<joint name='f' type='prismatic'><parent link='a'/><child link='c'/><axis xyz='0 1 0'/>"
           "<limit lower='-1' upper='1' effort='10' velocity='1'/>"
           "<mimic joint='m' multiplier='1' offset='0.1'/></joint></robot>" % (INERTIAL, INERTIAL, INERTIAL))
    world = World()
    m = world.add_urdf("mimic", xml, pose=((0, 0, 5), (0, 0, 0, 1)))
    assert m.joints["f"].position == pytest.approx(0.1, abs=1e-9)
    world.step(500)
    assert not world.pop_events()
    assert m.joints["f"].position == pytest.approx(m.joints["m"].position + 0.1, abs=1e-3)


def _runaway_world():
    """A slider pushed far beyond the guard's speed limit every step, beside a falling box."""
    world = World()
    m = world.add_urdf("slider", _slider(-100, 100), pose=((0, 0, 5), (0, 0, 0, 1)))
    box = world.add_urdf("box", H.fixture("box.urdf"), pose=((3, 0, 50), (0, 0, 0, 1)))
    m.joints["s"].effort_limit = 1e6
    world.add_step_hook(before=lambda t, dt: "slider" in world.models and m.joints["s"].set_effort(1e6))
    return world, m, box


def _step_until_frozen(world, limit=20000):
    for _ in range(limit):
        world.step(1)
        if world.frozen_models:
            return
    raise AssertionError("the guard never froze the model")


def test_the_guard_backs_off_and_freezes_only_the_model_that_keeps_blowing_up(caplog):
    from modrob_sim.physics import world as world_mod
    world, m, box = _runaway_world()
    with caplog.at_level(logging.ERROR, logger="modrob_sim.physics"):
        _step_until_frozen(world)   # never raises: stepping goes on
    assert list(world.frozen_models) == ["slider"]
    msg = world.frozen_models["slider"]
    assert "model 'slider' was restored %d times in a row" % world_mod.GUARD_STREAK_LIMIT in msg
    assert "FROZEN" in msg and "set_model_state" in msg and "delete_model" in msg
    assert any(msg in r.getMessage() for r in caplog.records)
    lines = [r for r in caplog.records if "blow-up guard" in r.getMessage()]
    assert len(lines) <= world.time + 3, (len(lines), world.time)  # one per model per simulated second
    events = world.pop_events()
    assert [e.model for e in events if e.reason == world_mod.FROZEN_REASON] == ["slider"]
    # the frozen model stands still and logs nothing more; the rest of the world goes on
    pose, t0, z0 = m.pose, world.time, box.pose[0][2]
    caplog.clear()
    with caplog.at_level(logging.ERROR, logger="modrob_sim.physics"):
        world.step(500)
    assert world.time == pytest.approx(t0 + 0.5)
    assert box.pose[0][2] < z0 - 0.5  # still falling
    assert m.pose == pose
    assert not world.pop_events() and not caplog.records


def test_a_frozen_model_is_released_by_set_state_reset_or_delete():
    world, m, box = _runaway_world()
    _step_until_frozen(world)
    m.set_pose(((0, 0, 6), (0, 0, 0, 1)))      # set_model_state
    assert not world.frozen_models
    world.step(1)
    assert world.pop_events()  # it moves (and blows up) again: the guard watches it again
    _step_until_frozen(world)
    m.set_configuration(["s"], [0.5])          # set_model_configuration
    assert not world.frozen_models
    _step_until_frozen(world)
    world.reset()                              # reset_simulation
    assert not world.frozen_models and world.time == 0.0
    _step_until_frozen(world)
    world.remove_model("slider")              # delete_model
    assert not world.frozen_models and "slider" not in world._guard_log
    world.pop_events()
    world.step(100)
    assert not world.pop_events()


def test_a_body_falling_on_a_frozen_model_does_not_move_it():
    world, m, box = _runaway_world()
    _step_until_frozen(world)
    pose = m.pose
    box.set_pose(((0, 0, 5.6), (0, 0, 0, 1)))  # above the frozen slider
    world.step(1000)
    assert m.pose == pose
    assert box.pose[0][2] > 5.0  # it rests on the frozen model instead of falling through


def test_spawn_initial_positions_are_bounded_like_set_configuration():
    world = scene()
    before = signature(world)
    with pytest.raises(ModelError, match="initial position 1e\\+12 of joint 's' is beyond"):
        world.add_urdf("s1", _slider(), pose=((3, 0, 1), (0, 0, 0, 1)), joint_positions={"s": 1e12})
    assert signature(world) == before
    m = world.add_urdf("s2", _slider(), pose=((3, 0, 1), (0, 0, 0, 1)), joint_positions={"s": 3.0})
    assert m.joints["s"].position == pytest.approx(0.5, abs=1e-9)
    world.step(10)

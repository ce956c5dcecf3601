"""Tier 1: worlds and models found and read as Gazebo finds and reads them.

- ``model://`` on Gazebo's model path: GAZEBO_MODEL_PATH, then the packages' exported
  gazebo_model_path folders, then ~/.gazebo/models; a model folder's SDF file chosen from its
  model.config as Gazebo chooses it;
- worlds (``worlds/x.world``) and ``file://media/...`` on the resource path, which packages extend
  with gazebo_media_path;
- a model that is nowhere on this machine (an <include>, or a model:// mesh: Gazebo's online
  database) is warned about once, naming the URI and where it looked, and the rest loads;
- nested models (turtlebot3_house) become scoped links of the outer model;
- SDF 1.0 (<gazebo version="1.0">) and pre-1.4 physics read as Gazebo 11 converts them.
"""
import logging
import math
import os
import textwrap

import pytest
import rospkg

from modrob_sim.errors import ModelError
from modrob_sim.gazebo_ros.package_exports import PackageExports
from modrob_sim.gazebo_ros.resources import ResourceResolver
from modrob_sim.gazebo_ros.world_file import find_world, world_physics
from modrob_sim.physics import World
from modrob_sim.physics.meshes import ResourceNotFound

HERE = os.path.dirname(os.path.abspath(__file__))
WORLDS = os.path.join(os.path.dirname(HERE), "fixtures", "worlds")
CUBE_STL = os.path.join(os.path.dirname(HERE), "fixtures", "physics")


def box_model(name, size=0.2, z=0.1, extra=""):
    return textwrap.dedent("""\
        <sdf version="1.6"><model name="{n}"><pose>0 0 {z} 0 0 0</pose><link name="link">
          <inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia></inertial>
          <collision name="c"><geometry><box><size>{s} {s} {s}</size></box></geometry></collision>{x}
        </link></model></sdf>""").format(n=name, s=size, z=z, x=extra)


def model_folder(root, name, sdf_text, config=None):
    d = os.path.join(root, name)
    os.makedirs(d)
    with open(os.path.join(d, "model.sdf"), "w") as f:
        f.write(sdf_text)
    if config is not None:
        with open(os.path.join(d, "model.config"), "w") as f:
            f.write(config)
    return d


def package(root, name, exports):
    d = os.path.join(root, name)
    os.makedirs(d)
    with open(os.path.join(d, "package.xml"), "w") as f:
        f.write('<?xml version="1.0"?><package format="2"><name>%s</name><version>0.0.1</version>'
                '<description>fixture</description><maintainer email="fixture@example.org">a</maintainer>'
                '<license>BSD</license><buildtool_depend>catkin</buildtool_depend><export>%s</export>'
                '</package>' % (name, exports))
    return d


@pytest.fixture
def places(tmp_path, monkeypatch):
    """GAZEBO_MODEL_PATH folder, a package exporting a model and a media path, and a HOME."""
    env_models = tmp_path / "env_models"
    env_models.mkdir()
    home = tmp_path / "home"
    (home / ".gazebo" / "models").mkdir(parents=True)
    monkeypatch.setenv("GAZEBO_MODEL_PATH", str(env_models))
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.delenv("GAZEBO_RESOURCE_PATH", raising=False)
    src = tmp_path / "ws" / "src"
    src.mkdir(parents=True)
    pkg = package(str(src), "world_pkg", '<gazebo_ros gazebo_model_path="${prefix}/models"/>'
                  '<gazebo_ros gazebo_media_path="${prefix}"/>')
    os.makedirs(os.path.join(pkg, "models"))
    os.makedirs(os.path.join(pkg, "worlds"))
    resolver = ResourceResolver(exports=PackageExports(rospkg.RosPack(ros_paths=[str(src)])))
    return {"env": str(env_models), "home": str(home / ".gazebo" / "models"),
            "pkg": pkg, "models": os.path.join(pkg, "models"), "resolver": resolver}


def test_model_path_order_env_then_exports_then_home(places):
    r = places["resolver"]
    for where in ("home", "models", "env"):
        model_folder(places[where], "shelf_" + where, box_model("shelf_" + where))
    model_folder(places["home"], "twice", box_model("twice_home"))
    model_folder(places["models"], "twice", box_model("twice_exported"))
    assert r.model_dirs() == [places["env"], places["models"], places["home"]]
    assert r("model://shelf_home/model.sdf") == os.path.join(places["home"], "shelf_home", "model.sdf")
    assert r("model://shelf_models") == os.path.join(places["models"], "shelf_models")
    assert r("model://twice").startswith(places["models"])          # exports before the home cache
    with pytest.raises(ResourceNotFound) as err:
        r("model://nowhere/meshes/x.dae")
    assert err.value.searched == r.model_dirs()
    assert "model://nowhere/meshes/x.dae" in str(err.value) and places["home"] in str(err.value)


def test_a_world_is_found_through_an_exported_media_path_and_a_missing_include_is_skipped(places, caplog):
    r = places["resolver"]
    model_folder(places["models"], "crate", box_model("crate", z=0.1),
                 '<model><name>crate</name><sdf version="1.6">model.sdf</sdf></model>')
    with open(os.path.join(places["pkg"], "worlds", "store.world"), "w") as f:
        f.write('<sdf version="1.6"><world name="default"><include><uri>model://ground_plane</uri></include>'
                '<include><uri>model://sun</uri></include>'
                '<include><uri>model://crate</uri><name>crate_a</name><pose>1 0 0.1 0 0 0</pose></include>'
                '<include><uri>model://database_only_chair</uri></include>'
                '<include><uri>model://crate</uri><name>crate_b</name><pose>2 0 0.1 0 0 0</pose></include>'
                '</world></sdf>')
    path = find_world("worlds/store.world", r)
    assert path == os.path.join(places["pkg"], "worlds", "store.world")
    world = World(resource_resolver=r)
    with caplog.at_level(logging.WARNING):
        models = world.add_sdf(open(path).read())
    assert [m.name for m in models] == ["ground_plane", "crate_a", "crate_b"]
    missing = [rec.getMessage() for rec in caplog.records if "database_only_chair" in rec.getMessage()]
    assert len(missing) == 1 and "skipped" in missing[0] and places["home"] in missing[0]
    world.step(200)
    assert world.models["crate_b"].pose[0][0] == pytest.approx(2.0, abs=1e-3)
    world.close()


def test_model_config_chooses_the_newest_sdf_gazebo_reads(places):
    r = places["resolver"]
    folder = model_folder(places["models"], "versions", box_model("from_model_sdf"),
                          '<model><name>v</name><sdf version="1.4">old.sdf</sdf>'
                          '<sdf version="1.6">new.sdf</sdf><sdf version="1.9">future.sdf</sdf></model>')
    for name in ("old", "new", "future"):
        with open(os.path.join(folder, name + ".sdf"), "w") as f:
            f.write(box_model("from_" + name))
    world = World(resource_resolver=r)
    models = world.add_sdf('<sdf version="1.6"><world name="w"><include><uri>model://versions</uri></include>'
                           '</world></sdf>')
    assert [m.name for m in models] == ["from_new"]
    world.close()


def test_an_offline_model_mesh_is_dropped_with_one_warning_and_a_found_one_kept(places, caplog):
    r = places["resolver"]
    mesh_dir = os.path.join(places["models"], "cube_kit", "meshes")
    os.makedirs(mesh_dir)
    with open(os.path.join(CUBE_STL, "cube_binary.stl"), "rb") as src:
        with open(os.path.join(mesh_dir, "cube.stl"), "wb") as dst:
            dst.write(src.read())

    def mesh(kind, name, uri):
        return '<%s name="%s"><geometry><mesh><uri>%s</uri></mesh></geometry></%s>' % (kind, name, uri, kind)
    text = box_model("kit", extra=mesh("collision", "gone", "model://mailbox_db/meshes/mailbox.dae")
                     + mesh("visual", "gone_v", "model://mailbox_db/meshes/mailbox.dae")
                     + mesh("visual", "kept", "model://cube_kit/meshes/cube.stl"))
    world = World(resource_resolver=r)
    with caplog.at_level(logging.WARNING):
        model = world.add_sdf(text)[0]
    warned = [rec.getMessage() for rec in caplog.records if "mailbox_db" in rec.getMessage()]
    assert len(warned) == 1 and "model 'kit' link 'link'" in warned[0] and "skipped" in warned[0]
    assert places["env"] in warned[0]
    # the offline visual is gone; the found one is a file:// path RViz can load
    assert [(g.name, g.uri) for g in model.links["link"].visuals] == [
        ("kept", "file://" + os.path.join(mesh_dir, "cube.stl"))]
    world.step(50)
    world.close()


def test_a_saved_worlds_state_places_its_models_as_gazebo_loads_it():
    """A world saved by Gazebo (husky_gazebo's clearpath_playpen) has a <state>: its models start
    at the state's poses, not their own; a model the state does not name keeps its pose."""
    from modrob_sim.physics.sdf_reader import read_sdf
    from modrob_sim.physics.transforms import quat_from_rpy

    def model(name, z):
        return ('<model name="%s"><static>true</static><pose>0 0 %r 0 0 0</pose><link name="link">'
                '<collision name="c"><geometry><box><size>1 1 1</size></box></geometry></collision>'
                '</link></model>' % (name, z))
    text = ('<sdf version="1.6"><world name="default">' + model("moved", 0.1) + model("kept", 0.3)
            + '<state world_name="default"><sim_time>12 0</sim_time><model name="moved">'
              '<pose>2 1 0.1 0 0 1.57</pose><link name="link"><pose>2 1 0.1 0 0 1.57</pose></link>'
              '</model></state></world></sdf>')
    descs, _settings = read_sdf(text, "w", lambda key, message: None)
    pose = dict((d.name, d.pose) for d in descs)
    assert tuple(pose["moved"][0]) == (2.0, 1.0, 0.1)
    assert pose["moved"][1] == pytest.approx(quat_from_rpy(0.0, 0.0, 1.57))
    assert tuple(pose["kept"][0]) == (0.0, 0.0, 0.3)


def test_a_missing_mesh_of_a_package_is_still_an_error(places):
    world = World(resource_resolver=places["resolver"])
    with pytest.raises(ModelError, match="package://world_pkg/meshes/none.stl"):
        world.add_sdf(box_model("k", extra='<collision name="m"><geometry><mesh><uri>'
                                "package://world_pkg/meshes/none.stl</uri></mesh></geometry></collision>"))
    world.close()


NESTED = """<sdf version="1.6"><model name="house"><static>true</static>
  <link name="wall"><pose>0 0 1 0 0 0</pose>
    <collision name="c"><geometry><box><size>4 0.1 2</size></box></geometry></collision></link>
  <model name="shelf"><static>1</static><pose frame="">2 1 0 0 0 1.5707963267948966</pose>
    <link name="link"><pose>0.5 0 0.5 0 0 0</pose>
      <collision name="c"><geometry><box><size>0.4 0.4 1</size></box></geometry></collision></link>
    <model name="book"><pose>0 0 1.1 0 0 0</pose>
      <link name="link">
        <collision name="c"><geometry><box><size>0.2 0.1 0.2</size></box></geometry></collision>
      </link></model>
  </model>
  <model name="lamp"><link name="link"><pose>-1 0 0.5 0 0 0</pose>
    <collision name="c"><geometry><sphere><radius>0.2</radius></sphere></geometry></collision></link></model>
</model></sdf>"""


def test_nested_models_become_scoped_links_with_composed_poses():
    world = World()
    house = world.add_sdf(NESTED)[0]
    assert sorted(house.links) == ["lamp::link", "shelf::book::link", "shelf::link", "wall"]
    (x, y, z), _ = house.links["shelf::link"].pose
    # (0.5, 0, 0.5) turned 90 degrees about z, then moved to (2, 1, 0)
    assert (x, y, z) == pytest.approx((2.0, 1.5, 0.5), abs=1e-9)
    assert house.links["shelf::book::link"].pose[0] == pytest.approx((2.0, 1.0, 1.1), abs=1e-9)
    world.close()


def test_a_nested_model_keeps_its_own_static_as_in_gazebo():
    """turtlebot3_house (static) holds a table with <static>0</static> and trash cans without
    <static>: in Gazebo those move (a nested model's <static> is its own, false when not given)."""
    world = World()
    house = world.add_sdf(NESTED)[0]
    static = {n: ln.is_static for n, ln in house.links.items()}
    assert static == {"wall": True, "shelf::link": True, "shelf::book::link": False, "lamp::link": False}
    world.step(300)     # nothing under the book and the lamp: they fall, the rest stays
    assert house.links["lamp::link"].pose[0][2] < 0.5 - 0.3
    assert house.links["shelf::book::link"].pose[0][2] < 1.1 - 0.3
    assert house.links["shelf::link"].pose[0] == pytest.approx((2.0, 1.5, 0.5), abs=1e-12)
    world.close()


def test_a_nested_include_static_overrides_and_a_link_left_without_collision_is_held(places, caplog):
    """An <include><static> overrides the included model's; a moving link whose every collision
    was an offline mesh (turtlebot3_house's mailbox) is held where it stands, not dropped through
    the world."""
    model_folder(places["models"], "crate", box_model("crate", z=0.1))
    text = ('<sdf version="1.6"><model name="house"><static>true</static>'
            '<link name="floor"><collision name="c"><geometry><box><size>4 4 0.1</size></box>'
            '</geometry></collision></link>'
            '<include><uri>model://crate</uri><name>held_crate</name><pose>1 0 1 0 0 0</pose>'
            '<static>true</static></include>'
            '<include><uri>model://crate</uri><name>loose_crate</name><pose>-1 0 1 0 0 0</pose></include>'
            '<model name="mailbox"><pose>0 1 0.5 0 0 0</pose><link name="link"><collision name="c">'
            '<geometry><mesh><uri>model://mailbox_db/meshes/mailbox.dae</uri></mesh></geometry>'
            '</collision></link></model></model></sdf>')
    world = World(resource_resolver=places["resolver"])
    with caplog.at_level(logging.WARNING):
        house = world.add_sdf(text)[0]
    held = [rec.getMessage() for rec in caplog.records if "no collision is left" in rec.getMessage()]
    assert len(held) == 1 and "link 'mailbox::link'" in held[0]
    static = {n: ln.is_static for n, ln in house.links.items()}
    assert static == {"floor": True, "held_crate::link": True, "loose_crate::link": False,
                      "mailbox::link": True}
    world.step(300)
    assert house.links["loose_crate::link"].pose[0][2] < 1.0 - 0.3     # falls (0.44 m in 0.3 s)
    assert house.links["held_crate::link"].pose[0][2] == pytest.approx(1.0, abs=1e-12)
    assert house.links["mailbox::link"].pose[0][2] == pytest.approx(0.5, abs=1e-12)
    world.close()


def test_sdf_1_0_world_reads_as_gazebo_11_converts_it(caplog):
    text = open(os.path.join(WORLDS, "sdf_1_0.world")).read()
    phys = world_physics(text)
    assert phys["time_step"] == 0.002 and phys["real_time_update_rate"] == 500.0
    assert phys["gravity"] == (0.0, 0.0, -9.5)
    world = World()
    with caplog.at_level(logging.WARNING):
        models = world.add_sdf(text, name="old")
    assert "SDF 1.0" in caplog.text
    assert [m.name for m in models] == ["floor", "crate", "swing"]
    assert world.time_step == 0.002 and world.gravity == (0.0, 0.0, -9.5)
    assert world.physics_params["iters"] == 40
    assert models[0].is_static and not models[1].is_static
    crate = models[1]
    (x, y, z), q = crate.pose
    assert (x, y, z) == pytest.approx((1.0, 2.0, 0.5))
    assert 2.0 * math.atan2(q[2], q[3]) == pytest.approx(0.3)
    assert crate.links["body"].mass == 2.0
    hinge = models[2].joints["hinge"]
    assert hinge.parent == "post" and hinge.child == "bob" and hinge.upper == 3.0
    world.step(1000)                                     # 2 s at the file's 2 ms
    assert crate.pose[0][2] == pytest.approx(0.1, abs=0.005)    # resting on the plane, half its height
    bob = models[2].links["bob"].pose[0]
    # the bob swings on its 0.5 m arm about the hinge at (-1, 0, 2), in the x-z plane
    assert math.dist(bob, (-1.0, 0.0, 2.0)) == pytest.approx(0.5, abs=0.005) and abs(bob[1]) < 1e-6
    assert bob[2] < 1.9
    world.close()


def test_pre_1_4_physics_elements_move_to_their_1_4_places():
    text = ('<sdf version="1.3"><world name="w"><physics type="ode"><update_rate>250</update_rate>'
            '<ode><solver><type>quick</type><dt>0.004</dt><iters>30</iters></solver></ode></physics>'
            '<include><uri>model://ground_plane</uri></include></world></sdf>')
    assert world_physics(text) == {"time_step": 0.004, "real_time_update_rate": 250.0}
    world = World()
    world.add_sdf(text)
    assert world.time_step == 0.004
    world.close()


def test_one_reader_of_a_worlds_physics_for_the_node_and_the_core():
    """world_physics (the node's pacing and step) and add_sdf (the core) read <physics> the same
    way: the same values, and the same refusal naming the element."""
    text = ('<sdf version="1.6"><world name="w"><gravity>0 0 -3</gravity><physics type="ode">'
            '<max_step_size>0.0025</max_step_size><real_time_factor>2</real_time_factor>'
            '<real_time_update_rate>800</real_time_update_rate></physics></world></sdf>')
    assert world_physics(text) == {"time_step": 0.0025, "real_time_factor": 2.0,
                                   "real_time_update_rate": 800.0, "gravity": (0.0, 0.0, -3.0)}
    world = World()
    world.add_sdf(text)
    assert world.time_step == 0.0025 and world.gravity == (0.0, 0.0, -3.0)
    world.close()
    bad = text.replace("0.0025", "fast")
    with pytest.raises(ModelError, match="max_step_size"):
        world_physics(bad)
    with pytest.raises(ModelError, match="max_step_size"):
        World().add_sdf(bad)


def test_a_world_plugin_is_warned_about_once_and_the_world_loads(caplog):
    text = ('<sdf version="1.6"><world name="w"><include><uri>model://ground_plane</uri></include>'
            '<plugin name="state" filename="libgazebo_ros_state.so"><update_rate>10</update_rate></plugin>'
            '<plugin name="state2" filename="libgazebo_ros_state.so"/></world></sdf>')
    world = World()
    with caplog.at_level(logging.WARNING):
        assert [m.name for m in world.add_sdf(text)] == ["ground_plane"]
    warned = [r.getMessage() for r in caplog.records if "libgazebo_ros_state.so" in r.getMessage()]
    assert len(warned) == 1 and "world plugins are not loaded" in warned[0]
    world.close()

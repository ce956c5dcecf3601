"""Nothing of a deleted model stays in the node's per-model structures (no master): the world
markers' and the scene's caches of visuals, the scene's tf link list, the guard's logs and
warnings, the plugin host. Each of these is keyed by model name, so a spawn/delete cycle with a
new name each time grew the /gazebo node's memory for ever (scripts/bench/spawn_delete_memory.py;
docs/benchmarks.md). Checked deterministically: the deleted Model object itself must be freed."""
import gc
import os
import weakref

from modrob_sim.camera.scene import SceneModel
from modrob_sim.gazebo_ros.markers import WorldMarkers
from modrob_sim.gazebo_ros.plugin_base import ModelPlugin
from modrob_sim.gazebo_ros.plugin_host import PluginHost
from modrob_sim.gazebo_ros.plugins import register_plugin

FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "sim")


def fixture(name):
    with open(os.path.join(FIXTURES, name)) as f:
        return f.read()


class _Probe(ModelPlugin):
    def before_step(self, t, dt):
        pass


register_plugin("libforget_probe.so", _Probe)


def _with_plugin(xml):
    plugin = "<gazebo><plugin name='p' filename='libforget_probe.so'/></gazebo>"
    return xml.replace("</robot>", plugin + "</robot>")


def test_a_deleted_model_leaves_no_cache_behind_and_is_freed():
    from modrob_sim.physics import World
    world = World(time_step=0.001)
    world.add_urdf("ground", fixture("ground.urdf"))
    props = WorldMarkers(world, "all")
    scene = SceneModel(world)
    host = PluginHost(world, "/gazebo", lambda uri: uri)
    refs = []
    for i in range(5):
        name = "arm_%d" % i               # a new name each cycle
        m = world.add_urdf(name, _with_plugin(fixture("arm2.urdf")), pose=((0, 0, 0.5), (0, 0, 0, 1)))
        host.load(m)
        refs.append(weakref.ref(m))
        assert props.update(force=True) is not None
        assert scene.changed() and scene.marker_array().markers
        world.step(5)
        host.unload(name)
        world.remove_model(name)
        del m
        props.update()
        scene.changed()
        assert set(props._visuals) <= {"ground"} and set(scene._visuals._visuals) <= {"ground"}
        assert all(k[0] == "ground" for k in props._last_poses)
        assert name not in host._loaded and not host._before
        assert name not in world._guard_log and name not in world.frozen_models
    gc.collect()
    alive = [r().name for r in refs if r() is not None]
    assert not alive, "deleted models still referenced: %s (%s)" % (
        alive, [type(o).__name__ for r in refs if r() is not None for o in gc.get_referrers(r())])


def test_the_scene_sends_its_tf_once_per_simulated_time():
    """The loop hands the scene the same simulated time after its steps and after the pass (and
    again and again while paused): a second /tf with that stamp is TF_REPEATED_DATA to every tf
    listener (seen on the TurtleBot3 stacks). Once per time, again for a listener that came since
    (a renderer started while paused); a reset's earlier time goes out."""
    from modrob_sim.camera.scene import ScenePublisher
    from modrob_sim.physics import World

    class Pub(object):
        def __init__(self):
            self.sent = []
            self.connections = 1

        def get_num_connections(self):
            return self.connections

        def publish(self, msg):
            self.sent.append(msg)
    world = World(time_step=0.001)
    world.add_urdf("ground", fixture("ground.urdf"))
    scene = ScenePublisher(world, rate=30.0)
    scene._tf_pub, scene._markers_pub = Pub(), Pub()
    for t, listeners in ((0.1, 1), (0.1, 1), (0.1, 1), (0.2, 1), (0.2, 2), (0.2, 2), (0.2, 1), (0.2, 1),
                         (0.05, 1)):
        scene._next_wall = 0.0           # the wall-clock period has passed every time
        scene._tf_pub.connections = listeners
        scene.after_step(t)
    stamps = [m.transforms[0].header.stamp.to_sec() for m in scene._tf_pub.sent]
    assert stamps == [0.1, 0.2, 0.2, 0.05]
    world.close()

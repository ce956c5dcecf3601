"""The simulator's whole scene for RViz and the camera renderer.

- ``/gazebo/scene_markers`` (visualization_msgs/MarkerArray, latched): every visual of every
  model (robots included, whether or not they have a robot_description), meshes with scale,
  URDF / ``Gazebo/<Name>`` colours. Each marker is frame-locked to its link's tf frame, so it is
  re-sent when models are spawned or deleted, and otherwise every ``MARKERS_AGAIN`` s of wall time
  while someone listens: RViz clears its displays when the clock jumps back (a simulator restart),
  and a latched message that reached it just before that was lost until the scene changed.
- tf ``world -> <prefix><model>/<link>`` for every link (and camera sensors' optical frames), at
  ``rate`` per wall-clock second, stamped with sim time (at most once per simulated time), only
  while someone listens to /tf.
"""
import time
import weakref

import rospy
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray

from modrob_sim.errors import SimulationError
from modrob_sim.gazebo_ros import markers
from modrob_sim.gazebo_ros import transforms as tf
from modrob_sim.gazebo_ros.native_pub import publisher

WORLD = "world"
MARKERS_AGAIN = 2.0     # s of wall time between two sends of an unchanged scene (while subscribed)


def link_frame(prefix, model_name, link_name):
    """The tf frame of a link in the scene: '<prefix><model>/<link>'."""
    return "%s%s/%s" % (prefix, model_name, link_name)


class SceneModel(object):
    """Pure: which links of which models carry visuals, and the MarkerArray for them."""

    def __init__(self, world, prefix="gazebo/"):
        self.world = world
        self.prefix = prefix
        self._visuals = markers.WorldMarkers(world, "all")   # parses visuals once per model
        self.extra_frames = {}          # child frame -> (model, link, offset pose): camera frames
        self._signature = None

    def links(self):
        """[(model, link_name, link)] of every link of every model (end-effector frames have no
        visuals but cameras are placed relative to them)."""
        out = []
        for m in list(self.world.models.values()):
            for ln in sorted(m.links):
                out.append((m, ln, m.links[ln]))
        return out

    def changed(self):
        sig = tuple((m.name, id(m)) for m in self.world.models.values())
        if sig != self._signature:
            self._signature = sig
            self._visuals.forget_removed()
            return True
        return False

    def marker_array(self, stamp=None):
        arr = MarkerArray()
        clear = Marker()
        clear.header.frame_id = WORLD
        clear.action = Marker.DELETEALL
        arr.markers.append(clear)
        for m in list(self.world.models.values()):
            i = 0
            for lname, visuals in self._visuals._model_visuals(m).items():
                for v in visuals:
                    mk = markers.WorldMarkers._marker(m.name, i, v.origin, v)
                    if mk is None:
                        continue
                    mk.header.frame_id = link_frame(self.prefix, m.name, lname)
                    if stamp is not None:
                        mk.header.stamp = stamp
                    mk.frame_locked = True
                    arr.markers.append(mk)
                    i += 1
        return arr


class ScenePublisher(object):
    """ROS side; ``after_step(sim_time)`` is called by the /gazebo loop after every step."""

    _by_world = weakref.WeakKeyDictionary()

    @classmethod
    def for_world(cls, world, rate=30.0, prefix="gazebo/"):
        """The one publisher of ``world`` (created on first use; the node and camera plugins share it)."""
        pub = cls._by_world.get(world)
        if pub is None:
            pub = cls._by_world[world] = cls(world, rate, prefix)
        return pub

    def __init__(self, world, rate=30.0, prefix="gazebo/"):
        self.model = SceneModel(world, prefix)
        self.period = 1.0 / rate if rate > 0 else 0.0
        # through roscpp when the node publishes natively: each subscriber (the renderer has two,
        # its rospy node and RViz) costs a rospy publisher a Python thread wake-up under the GIL
        self._markers_pub = publisher("/gazebo/scene_markers", MarkerArray, queue_size=1, latch=True)
        self._tf_pub = publisher("/tf", TFMessage, queue_size=10)
        self._next_wall = 0.0
        self._markers_again = 0.0
        self._links = []
        self._tf_time = None        # the simulated time of the last /tf sent ...
        self._tf_listeners = 0      # ... and to how many

    def link_frame(self, model_name, link_name):
        return link_frame(self.model.prefix, model_name, link_name)

    def forget_removed(self):
        """Deleted models leave the cached link list and visuals now, not at the next tf tick."""
        live = self.model.world.models
        self._links = [item for item in self._links if live.get(item[0].name) is item[0]]
        self.model._visuals.forget_removed()
        self.model._signature = None

    def add_frame(self, child, model_name, link_name, offset):
        """Publish ``child`` at ``offset`` (pose in the link frame) from the link, in tf."""
        self.model.extra_frames[child] = (model_name, link_name, offset)
        self.model._signature = None

    def remove_frame(self, child):
        self.model.extra_frames.pop(child, None)
        self.model._signature = None

    def after_step(self, sim_time):
        if self.period <= 0.0:
            return
        wall = time.monotonic()
        if wall < self._next_wall:
            return
        self._next_wall = wall + self.period
        stamp = rospy.Time.from_sec(sim_time)
        if self.model.changed():
            self._links = self.model.links()
            self._markers_pub.publish(self.model.marker_array())
            self._markers_again = wall + MARKERS_AGAIN
        elif wall >= self._markers_again and self._markers_pub.get_num_connections() > 0:
            again = self.model.marker_array()
            del again.markers[:1]           # the same markers again, without DELETEALL: RViz
            self._markers_pub.publish(again)    # modifies them in place, nothing blinks
            self._markers_again = wall + MARKERS_AGAIN
        # once per simulated time: the loop calls this after its steps and after each pass, and a
        # second message with the same stamp is TF_REPEATED_DATA to every tf listener (also while
        # paused); again only for a listener that came since (a renderer started while paused
        # needs the frames). After a reset the clock goes back and the frames go out again.
        listeners = self._tf_pub.get_num_connections()
        if listeners == 0 or (self._tf_time == sim_time and listeners <= self._tf_listeners):
            self._tf_listeners = min(self._tf_listeners, listeners)
            return
        self._tf_time, self._tf_listeners = sim_time, listeners
        msg = TFMessage()
        poses = {}
        for m, lname, link in self._links:
            try:
                pose = link.pose
            except SimulationError:     # deleted between two calls: skip it this time
                continue
            frame = link_frame(self.model.prefix, m.name, lname)
            poses[(m.name, lname)] = pose
            msg.transforms.append(self._transform(stamp, frame, pose))
        for child, (mname, lname, offset) in self.model.extra_frames.items():
            pose = poses.get((mname, lname))
            if pose is not None:
                msg.transforms.append(self._transform(stamp, child, tf.compose(pose, offset)))
        if msg.transforms:
            self._tf_pub.publish(msg)

    @staticmethod
    def _transform(stamp, child, pose):
        (p, q) = pose
        t = TransformStamped()
        t.header.stamp = stamp
        t.header.frame_id = WORLD
        t.child_frame_id = child
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = p
        (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z, t.transform.rotation.w) = q
        return t

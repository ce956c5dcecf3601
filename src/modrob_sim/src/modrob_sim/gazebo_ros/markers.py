"""The world's props and static objects as a visualization_msgs/MarkerArray, so RViz shows what
gzclient would (robots with joints are shown by RViz's RobotModel from robot_description).

``WorldMarkers(world, which).update(force)`` returns a MarkerArray when something changed (a
model spawned or deleted, a prop moved) or when forced, else None. ``which``: "props" (models
without driven joints: static objects, loose objects, a world file's models of several free or
welded links, the ground), "all" or "none".
"""
import collections
import os

from geometry_msgs.msg import Pose
from visualization_msgs.msg import Marker, MarkerArray

from modrob_sim.errors import InputError
from modrob_sim.gazebo_ros import transforms as tf

#: one visual of a link: origin = pose of the geometry in the LINK frame, kind one of box /
#: cylinder / sphere / mesh / plane
Visual = collections.namedtuple("Visual", "link origin kind size filename scale rgba")

DEFAULT_RGBA = (0.7, 0.7, 0.7, 1.0)

#: Colours of Gazebo's stock materials (Gazebo/<Name>), as gzclient shows them.
GAZEBO_MATERIALS = {
    "Gazebo/White": (1.0, 1.0, 1.0, 1.0), "Gazebo/Grey": (0.7, 0.7, 0.7, 1.0),
    "Gazebo/Gray": (0.7, 0.7, 0.7, 1.0), "Gazebo/DarkGrey": (0.35, 0.35, 0.35, 1.0),
    "Gazebo/DarkGray": (0.35, 0.35, 0.35, 1.0), "Gazebo/Black": (0.05, 0.05, 0.05, 1.0),
    "Gazebo/Red": (1.0, 0.0, 0.0, 1.0), "Gazebo/RedBright": (0.87, 0.26, 0.07, 1.0),
    "Gazebo/Green": (0.0, 1.0, 0.0, 1.0), "Gazebo/Blue": (0.0, 0.0, 1.0, 1.0),
    "Gazebo/SkyBlue": (0.53, 0.81, 0.92, 1.0), "Gazebo/Yellow": (1.0, 1.0, 0.0, 1.0),
    "Gazebo/Orange": (1.0, 0.5, 0.09, 1.0), "Gazebo/Purple": (0.5, 0.0, 0.5, 1.0),
    "Gazebo/Turquoise": (0.0, 0.8, 0.8, 1.0), "Gazebo/Wood": (0.55, 0.37, 0.2, 1.0),
    "Gazebo/WoodFloor": (0.6, 0.45, 0.3, 1.0), "Gazebo/Indigo": (0.29, 0.0, 0.51, 1.0),
    "Gazebo/ZincYellow": (0.9, 0.85, 0.0, 1.0), "Gazebo/Residential": (0.85, 0.8, 0.7, 1.0),
}

FRAME = "world"
MOVE_TOLERANCE = 1e-4      # m and rad: smaller motions do not republish


def _wanted(model, which):
    if which == "all":
        return True
    if which == "none":
        return False
    # a world file's model of several links without joints between them (a parking lot's asphalt
    # and paint, a ramp's three boxes) holds them with "floating" joints: nothing drives them, and
    # no robot_description covers them for RViz's RobotModel
    return all(j.type in ("fixed", "floating") for j in model.joints.values())


def _mesh_uri(filename):
    if "://" in filename:
        return filename
    return "file://" + os.path.abspath(filename)


def _from_core(link_name, link, g):
    """A Visual from the core's GeometryDesc (kind, size, origin, uri, color, material)."""
    gz = GAZEBO_MATERIALS
    rgba = gz.get(getattr(link, "material", None) or "") or g.color or gz.get(g.material or "")
    if g.kind == "plane":
        size, scale = (100.0, 100.0), (1.0, 1.0, 1.0)
    elif g.kind == "mesh":
        size, scale = (), tuple(g.size) if g.size else (1.0, 1.0, 1.0)
    else:
        size, scale = tuple(g.size), (1.0, 1.0, 1.0)
    return Visual(link_name, g.origin, g.kind, size, g.uri, scale, tuple(rgba) if rgba else DEFAULT_RGBA)


class WorldMarkers(object):
    def __init__(self, world, which="props"):
        if which not in ("props", "all", "none"):
            raise InputError("~marker_models must be props, all or none, got %r" % which)
        self.world = world
        self.which = which
        self._visuals = {}          # model name -> {link: [Visual]} (parsed once per model)
        self._last_poses = {}       # (model, link) -> pose published last
        self._models = ()

    def _model_visuals(self, model):
        vis = self._visuals.get(model.name)
        if vis is None or vis[0] is not model:
            per_link = {}
            for lname, link in model.links.items():
                v = [_from_core(lname, link, g) for g in link.visuals]
                if v:
                    per_link[lname] = v
            vis = (model, per_link)
            self._visuals[model.name] = vis
        return vis[1]

    def forget_removed(self):
        """Drop the cached visuals of models no longer in the world (each entry holds a whole
        Model: keyed by name, a spawn/delete cycle with a new name each time grew it for ever)."""
        live = self.world.models
        for name in [n for n, (m, _) in self._visuals.items() if live.get(n) is not m]:
            del self._visuals[name]
        for key in [k for k in self._last_poses if k[0] not in live]:
            del self._last_poses[key]

    def update(self, force=False):
        models = [m for m in self.world.models.values() if _wanted(m, self.which)]
        names = tuple(m.name for m in models)
        poses = {}
        for m in models:
            for lname in self._model_visuals(m):
                link = m.links.get(lname)
                if link is not None:
                    poses[(m.name, lname)] = link.pose
        if not force and names == self._models and not self._moved(poses):
            return None
        self._models = names
        self._last_poses = poses
        self.forget_removed()
        return self._build(models, poses)

    def _moved(self, poses):
        if set(poses) != set(self._last_poses):
            return True
        for key, pose in poses.items():
            d, a = tf.pose_distance(pose, self._last_poses[key])
            if d > MOVE_TOLERANCE or a > MOVE_TOLERANCE:
                return True
        return False

    def _build(self, models, poses):
        arr = MarkerArray()
        clear = Marker()
        clear.header.frame_id = FRAME
        clear.action = Marker.DELETEALL
        arr.markers.append(clear)
        for m in models:
            i = 0
            for lname, visuals in self._model_visuals(m).items():
                link_pose = poses.get((m.name, lname))
                if link_pose is None:
                    continue
                for v in visuals:
                    mk = self._marker(m.name, i, tf.compose(link_pose, v.origin), v)
                    if mk is not None:
                        arr.markers.append(mk)
                        i += 1
        return arr

    @staticmethod
    def _marker(ns, idx, pose, v):
        mk = Marker()
        mk.header.frame_id = FRAME
        mk.ns = ns
        mk.id = idx
        mk.action = Marker.ADD
        mk.frame_locked = False
        (mk.color.r, mk.color.g, mk.color.b, mk.color.a) = v.rgba
        if v.kind == "box":
            mk.type = Marker.CUBE
            mk.scale.x, mk.scale.y, mk.scale.z = v.size
        elif v.kind == "cylinder":
            mk.type = Marker.CYLINDER
            mk.scale.x = mk.scale.y = 2.0 * v.size[0]
            mk.scale.z = v.size[1]
        elif v.kind == "sphere":
            mk.type = Marker.SPHERE
            mk.scale.x = mk.scale.y = mk.scale.z = 2.0 * v.size[0]
        elif v.kind == "plane":
            mk.type = Marker.CUBE
            mk.scale.x, mk.scale.y = v.size
            mk.scale.z = 0.002
            # top 3 mm under the plane: RViz's grid at z = 0 stays visible (no z-fighting)
            pose = tf.compose(pose, ((0.0, 0.0, -0.004), (0.0, 0.0, 0.0, 1.0)))
        elif v.kind == "mesh" and v.filename:
            mk.type = Marker.MESH_RESOURCE
            mk.mesh_resource = _mesh_uri(v.filename)
            mk.mesh_use_embedded_materials = False
            mk.scale.x, mk.scale.y, mk.scale.z = v.scale
        else:
            return None
        p = Pose()
        (p.position.x, p.position.y, p.position.z) = pose[0]
        (p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w) = pose[1]
        mk.pose = p
        return mk

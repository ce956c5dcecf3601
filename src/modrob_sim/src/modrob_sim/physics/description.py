"""Engine-neutral description of a model, produced by the URDF and SDF readers and consumed by the
builder. Nothing here touches ODE; everything is validated plain data."""
from collections import OrderedDict, namedtuple

from .transforms import IDENTITY_POSE

#: every <gazebo><plugin> / SDF <plugin>. ``link`` and ``sensor`` (additions to the contract) are
#: set for plugins inside a <sensor>: the link name and the <sensor> Element.
PluginSpec = namedtuple("PluginSpec", "name filename element robot_namespace link sensor")
PluginSpec.__new__.__defaults__ = (None, None)

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")

# Gazebo's (SDF's) defaults for a collision surface.
DEFAULT_MU = 1.0
DEFAULT_KP = 1e12
DEFAULT_KD = 1.0
DEFAULT_MAX_VEL = 0.01
#: minDepth not given: the world's contact_surface_layer (SDF's default is 0; see docs/physics.md)
DEFAULT_MIN_DEPTH = None


class Surface(object):
    """Contact surface of one collision (Gazebo: per link from <gazebo reference>, per collision
    in SDF). ``max_contacts``: the collision's own cap of contacts per pair (URDF <maxContacts>,
    SDF <collision><max_contacts>); 0 = only the world's."""
    __slots__ = ("mu1", "mu2", "kp", "kd", "max_vel", "min_depth", "fdir1", "max_contacts")

    def __init__(self, mu1=DEFAULT_MU, mu2=DEFAULT_MU, kp=DEFAULT_KP, kd=DEFAULT_KD,
                 max_vel=DEFAULT_MAX_VEL, min_depth=DEFAULT_MIN_DEPTH, fdir1=(0.0, 0.0, 0.0),
                 max_contacts=0):
        self.mu1, self.mu2, self.kp, self.kd = mu1, mu2, kp, kd
        self.max_vel, self.min_depth = max_vel, min_depth
        self.fdir1 = fdir1  # direction of mu1 in the collision frame; (0, 0, 0) = not given
        self.max_contacts = max_contacts

    def copy(self):
        return Surface(self.mu1, self.mu2, self.kp, self.kd, self.max_vel, self.min_depth, self.fdir1,
                       self.max_contacts)

    def key(self):
        """The surface as the C loop's mr_set_surface takes it (minDepth not given: -1)."""
        return (self.mu1, self.mu2, self.kp, self.kd, self.max_vel,
                -1.0 if self.min_depth is None else self.min_depth) + tuple(self.fdir1) + (self.max_contacts,)


class GeometryDesc(object):
    """One <collision> or <visual>. ``kind`` is box | cylinder | sphere | plane | mesh.
    size: box (x, y, z); cylinder (radius, length); sphere (radius,); plane (nx, ny, nz) normal
    (SDF <plane><normal>, size ignored); mesh: the scale (sx, sy, sz). ``origin`` is the pose in
    the link frame. For meshes ``uri`` is the file name as written; the builder resolves it."""

    def __init__(self, kind, size, origin=IDENTITY_POSE, uri=None, name=None, surface=None,
                 material=None, color=None):
        self.kind = kind
        self.size = tuple(size)
        self.origin = origin
        self.uri = uri
        self.name = name
        self.surface = surface
        self.material = material
        self.color = color

    def __repr__(self):
        return "GeometryDesc(%s %r at %r%s)" % (self.kind, self.size, self.origin,
                                                " " + self.uri if self.uri else "")


class LinkDesc(object):
    def __init__(self, name):
        self.name = name
        self.mass = 0.0
        self.inertial_origin = IDENTITY_POSE  # pose of the inertial frame in the link frame
        self.inertia = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)  # ixx ixy ixz iyy iyz izz, inertial frame
        self.has_inertial = False
        self.collisions = []
        self.visuals = []
        self.surface = Surface()
        self.self_collide = False
        self.gravity = True
        self.material = None
        self.sensors = []  # xml Elements of <sensor> (Gazebo extension or SDF)
        self.pose = None   # SDF only: link pose in the model frame (URDF: from joints)
        self.static = None  # SDF: a nested model's own <static>; None: the model's
        self.extra = {}    # accepted Gazebo tags without physics meaning (kept for plugins)


class JointDesc(object):
    def __init__(self, name, jtype, parent, child):
        self.name = name
        self.type = jtype
        self.parent = parent
        self.child = child
        self.origin = IDENTITY_POSE  # pose of the joint frame in the parent link frame
        self.child_offset = IDENTITY_POSE  # pose of the child link in the joint frame (SDF)
        self.axis = (1.0, 0.0, 0.0)
        self.lower = None
        self.upper = None
        self.effort_limit = None
        self.velocity_limit = None
        self.damping = 0.0
        self.friction = 0.0
        self.mimic = None  # (joint_name, multiplier, offset)
        self.extra = {}


class ModelDesc(object):
    def __init__(self, name, kind, source_xml):
        self.name = name
        self.kind = kind
        self.source_xml = source_xml
        self.links = OrderedDict()
        self.joints = OrderedDict()
        self.plugins = []
        self.grippers = []  # GripperDesc of every <gripper> (Gazebo's grasp check)
        self.static = False
        self.self_collide = False
        self.pose = None  # SDF <model><pose>, in the frame of the spawn pose (World.add_sdf)
        self.root = None  # root link name (may be "world")
        self.root_offset = IDENTITY_POSE  # SDF: root link pose in the model frame

    def link_static(self, ld):
        """Whether the link ``ld`` is static: its nested model's <static>, else the model's."""
        return self.static if ld.static is None else ld.static

"""The module database (modrob_description/config/Modules.csv): loading, validation, and the
geometry of each module kind.

A module is described in its own frame: z points along the kinematic chain, from the proximal
mounting face (z = 0) to the distal one (z = length). Rigid modules (``base``, ``link``) are one
body. Joint modules (``joint_inline``, ``joint_elbow``) are two bodies: the *housing* (motor and
harmonic drive, fixed to the previous module) and the *output* (fixed to the next module), joined
by a revolute joint at z = joint_offset about ``axis`` (z for inline joints, x or y for elbows).
The output body's frame sits on the joint, so its distal face is at z = length - joint_offset.
"""
import csv
import math
import os

from modrob_build.errors import DatabaseError
from modrob_build import shapes

KINDS = ("base", "link", "joint_inline", "joint_elbow")
JOINT_KINDS = ("joint_inline", "joint_elbow")

# column -> (type, required for which kinds, check)
_POS = "positive"
_NONNEG = "non-negative"
COLUMNS = [
    ("id", "int", KINDS, None),
    ("name", "str", KINDS, None),
    ("kind", "str", KINDS, None),
    ("radius", "float", KINDS, _POS),
    ("wall", "float", ("link",), _POS),
    ("length", "float", KINDS, _POS),
    ("joint_offset", "float", JOINT_KINDS, _POS),
    ("axis", "str", JOINT_KINDS, None),
    ("mass_in", "float", KINDS, _POS),
    ("com_in_z", "float", KINDS, None),
    ("ixx_in", "float", KINDS, _POS),
    ("iyy_in", "float", KINDS, _POS),
    ("izz_in", "float", KINDS, _POS),
    ("mass_out", "float", JOINT_KINDS, _POS),
    ("com_out_z", "float", JOINT_KINDS, None),
    ("ixx_out", "float", JOINT_KINDS, _POS),
    ("iyy_out", "float", JOINT_KINDS, _POS),
    ("izz_out", "float", JOINT_KINDS, _POS),
    ("lower", "float", JOINT_KINDS, None),
    ("upper", "float", JOINT_KINDS, None),
    ("effort", "float", JOINT_KINDS, _POS),
    ("velocity", "float", JOINT_KINDS, _POS),
    ("damping", "float", JOINT_KINDS, _NONNEG),
    ("friction", "float", JOINT_KINDS, _NONNEG),
    ("reduction", "float", JOINT_KINDS, _POS),
    ("armature", "float", JOINT_KINDS, _NONNEG),
    ("mu1", "float", KINDS, _NONNEG),
    ("mu2", "float", KINDS, _NONNEG),
    ("rgba", "rgba", KINDS, None),
    ("gazebo_material", "str", KINDS, None),
    ("description", "str", (), None),
]
COLUMN_NAMES = [c[0] for c in COLUMNS]
AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


def default_database_path():
    """Modules.csv of the modrob_description package (rospkg, else the source tree)."""
    try:
        import rospkg
        root = rospkg.RosPack().get_path("modrob_description")
    except Exception:  # noqa: B902 - rospkg raises its own types or is not configured
        root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                            "modrob_description")
    return os.path.normpath(os.path.join(root, "config", "Modules.csv"))


class Shape(object):
    """A primitive of a module body: cylinder (axis 'x'|'y'|'z') or tube, centre in the body frame."""

    def __init__(self, kind, radius, length, center, axis, mass, inner_radius=None):
        self.kind = kind              # "cylinder" | "tube"
        self.radius = radius
        self.length = length
        self.center = center
        self.axis = axis
        self.mass = mass
        self.inner_radius = inner_radius

    def inertia(self):
        if self.kind == "tube":
            base = shapes.tube_inertia(self.mass, self.radius, self.inner_radius, self.length)
        else:
            base = shapes.solid_cylinder_inertia(self.mass, self.radius, self.length)
        return shapes.rotate_to_axis(base, self.axis)


class Body(object):
    """One rigid body of a module, in its own frame."""

    def __init__(self, role, shapes_, mass, com_z, inertia, distal_z):
        self.role = role          # "body" (rigid module), "housing" or "output" (joint module)
        self.shapes = shapes_
        self.mass = mass
        self.com_z = com_z
        self.inertia = inertia    # (ixx, iyy, izz) about the COM, body frame axes
        self.distal_z = distal_z  # where the next thing attaches (z in this body's frame)


class Module(object):
    """One row of Modules.csv."""

    def __init__(self, row, source):
        self.source = source      # "file:line" for messages
        for name, typ, _, _ in COLUMNS:
            setattr(self, name, row.get(name))

    @property
    def is_joint(self):
        return self.kind in JOINT_KINDS

    @property
    def axis_vector(self):
        return AXES[self.axis] if self.is_joint else None

    def shapes_by_role(self):
        """Geometry of each body from the primary columns (radius, wall, length, offset, masses)."""
        r, length = self.radius, self.length
        if self.kind == "base":
            return {"body": [Shape("cylinder", r, length, (0, 0, length / 2), "z", self.mass_in)]}
        if self.kind == "link":
            return {"body": [Shape("tube", r, length, (0, 0, length / 2), "z", self.mass_in,
                                   inner_radius=r - self.wall)]}
        j = self.joint_offset
        if self.kind == "joint_inline":
            return {"housing": [Shape("cylinder", r, j, (0, 0, j / 2), "z", self.mass_in)],
                    "output": [Shape("cylinder", r, length - j, (0, 0, (length - j) / 2), "z",
                                     self.mass_out)]}
        # elbow: a stem up to the hinge barrel (a cylinder of radius r and length 2r along the
        # joint axis, centred on the joint), the housing mass split by volume; the output is a
        # stem from the barrel's surface to the distal face.
        stem = j - r
        stem_mass = self.mass_in * stem / (stem + 2 * r)
        out_len = length - j - r
        return {"housing": [Shape("cylinder", r, stem, (0, 0, stem / 2), "z", stem_mass),
                            Shape("cylinder", r, 2 * r, (0, 0, j), self.axis,
                                  self.mass_in - stem_mass)],
                "output": [Shape("cylinder", r, out_len, (0, 0, r + out_len / 2), "z",
                                 self.mass_out)]}

    def derived_mass_properties(self):
        """{role: (mass, com_z, (ixx, iyy, izz))} computed from the shapes (what the inertia
        columns must hold)."""
        out = {}
        for role, shs in self.shapes_by_role().items():
            mass, com, inertia = shapes.combine(
                [shapes.Part(s.mass, s.center, s.inertia()) for s in shs])
            out[role] = (mass, com[2], inertia)
        return out

    def bodies(self):
        """Bodies with the mass properties stored in the database."""
        shs = self.shapes_by_role()
        if not self.is_joint:
            return [Body("body", shs["body"], self.mass_in, self.com_in_z,
                         (self.ixx_in, self.iyy_in, self.izz_in), self.length)]
        return [Body("housing", shs["housing"], self.mass_in, self.com_in_z,
                     (self.ixx_in, self.iyy_in, self.izz_in), self.joint_offset),
                Body("output", shs["output"], self.mass_out, self.com_out_z,
                     (self.ixx_out, self.iyy_out, self.izz_out), self.length - self.joint_offset)]


class ModuleDatabase(object):
    """The modules by ID, in file order."""

    def __init__(self, modules, path):
        self.path = path
        self.modules = modules            # dict id -> Module (insertion = file order)

    def __contains__(self, module_id):
        return module_id in self.modules

    def __getitem__(self, module_id):
        return self.modules[module_id]

    def ids(self, kind=None):
        return [m.id for m in self.modules.values() if kind is None or m.kind == kind]

    def base_ids(self):
        return self.ids("base")


def _parse_value(typ, text, where):
    text = text.strip()
    if typ == "str":
        return text
    if typ == "int":
        try:
            return int(text)
        except ValueError:
            raise DatabaseError("%s: '%s' is not an integer" % (where, text))
    if typ == "float":
        try:
            value = float(text)
        except ValueError:
            raise DatabaseError("%s: '%s' is not a number" % (where, text))
        if not math.isfinite(value):
            raise DatabaseError("%s: '%s' is not a finite number" % (where, text))
        return value
    if typ == "rgba":
        parts = text.split()
        try:
            values = tuple(float(p) for p in parts)
        except ValueError:
            values = ()
        if len(values) != 4 or not all(0.0 <= v <= 1.0 for v in values):
            raise DatabaseError("%s: '%s' is not an RGBA colour (four numbers 0..1 separated by "
                                "spaces, e.g. '0.1 0.1 0.8 1')" % (where, text))
        return values
    raise AssertionError(typ)


def load_database(path=None):
    """Read and validate Modules.csv. Raises DatabaseError naming file, line and column."""
    path = path or default_database_path()
    try:
        with open(path, newline="") as f:
            lines = [(n, line) for n, line in enumerate(f, start=1)]
    except OSError as e:
        raise DatabaseError("cannot read the module database %s: %s" % (path, e.strerror))
    data = [(n, line) for n, line in lines if line.strip() and not line.lstrip().startswith("#")]
    if not data:
        raise DatabaseError("%s: the module database is empty (expected a header line with the "
                            "columns %s)" % (path, ", ".join(COLUMN_NAMES)))
    header_line, header_text = data[0]
    header = [h.strip() for h in next(csv.reader([header_text]))]
    missing = [c for c in COLUMN_NAMES if c not in header]
    if missing:
        raise DatabaseError("%s:%d: header lacks column(s) %s" % (path, header_line, ", ".join(missing)))
    unknown = [h for h in header if h not in COLUMN_NAMES]
    if unknown:
        raise DatabaseError("%s:%d: unknown column(s) %s (known: %s)"
                            % (path, header_line, ", ".join(unknown), ", ".join(COLUMN_NAMES)))
    modules = {}
    for line_no, text in data[1:]:
        cells = next(csv.reader([text]))
        if len(cells) != len(header):
            raise DatabaseError("%s:%d: %d cells, the header has %d columns"
                                % (path, line_no, len(cells), len(header)))
        raw = dict(zip(header, cells))
        kind = raw["kind"].strip()
        if kind not in KINDS:
            raise DatabaseError("%s:%d: column 'kind': '%s' is not one of %s"
                                % (path, line_no, kind, ", ".join(KINDS)))
        row = {}
        for name, typ, required_for, check in COLUMNS:
            where = "%s:%d: column '%s'" % (path, line_no, name)
            text_value = raw[name].strip()
            if not text_value:
                if kind in required_for:
                    raise DatabaseError("%s: empty, but a %s module needs it" % (where, kind))
                row[name] = None
                continue
            value = _parse_value(typ, text_value, where)
            if check == _POS and value <= 0.0:
                raise DatabaseError("%s: %s must be > 0" % (where, text_value))
            if check == _NONNEG and value < 0.0:
                raise DatabaseError("%s: %s must be >= 0" % (where, text_value))
            row[name] = value
        where = "%s:%d" % (path, line_no)
        if row["id"] in modules:
            raise DatabaseError("%s: column 'id': ID %d already defined at %s"
                                % (where, row["id"], modules[row["id"]].source))
        if kind in JOINT_KINDS:
            if row["axis"] not in AXES:
                raise DatabaseError("%s: column 'axis': '%s' is not x, y or z" % (where, row["axis"]))
            if kind == "joint_inline" and row["axis"] != "z":
                raise DatabaseError("%s: column 'axis': an inline joint turns about the chain (z)"
                                    % where)
            if kind == "joint_elbow" and row["axis"] == "z":
                raise DatabaseError("%s: column 'axis': an elbow joint turns about x or y" % where)
            if not row["lower"] < row["upper"]:
                raise DatabaseError("%s: column 'upper': upper limit %g is not above lower %g"
                                    % (where, row["upper"], row["lower"]))
            if not row["joint_offset"] < row["length"]:
                raise DatabaseError("%s: column 'joint_offset': %g must lie inside the module "
                                    "(length %g)" % (where, row["joint_offset"], row["length"]))
            if kind == "joint_elbow" and not (row["radius"] < row["joint_offset"]
                                              < row["length"] - row["radius"]):
                raise DatabaseError("%s: column 'joint_offset': an elbow's hinge barrel (radius %g) "
                                    "must fit between the faces" % (where, row["radius"]))
        if kind == "link" and not row["wall"] < row["radius"]:
            raise DatabaseError("%s: column 'wall': %g must be thinner than the radius %g"
                                % (where, row["wall"], row["radius"]))
        module = Module(row, where)
        for body in module.bodies():
            if not shapes.satisfies_triangle_inequality(body.inertia):
                raise DatabaseError("%s: columns 'ixx/iyy/izz_%s': %s is not a physical inertia "
                                    "(each moment must not exceed the sum of the other two)"
                                    % (where, "out" if body.role == "output" else "in", body.inertia))
        modules[row["id"]] = module
    if not any(m.kind == "base" for m in modules.values()):
        raise DatabaseError("%s: no module of kind 'base'" % path)
    return ModuleDatabase(modules, path)

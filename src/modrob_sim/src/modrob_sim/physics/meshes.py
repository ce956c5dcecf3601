"""Collision mesh files -> triangles: STL (binary and ASCII), Wavefront OBJ and a minimal COLLADA
(DAE) reader, plus URI resolution (package://, file://, model://, plain paths).

A mesh is returned as ``(vertices, triangles)``: a list of (x, y, z) in metres (file units times
the DAE <unit meter>, before the URDF <mesh scale>) and a list of (i, j, k) vertex indices.
Errors raise MeshError with the file and the reason; the World turns them into ModelError naming
the model, the link and the URI.
"""
import math
import os
import re
import struct
import xml.etree.ElementTree as ET

from ..errors import ModelError


class MeshError(ModelError):
    pass


# ---- URI resolution -----------------------------------------------------------------------------
class ResourceNotFound(MeshError):
    """A URI that names no file on this machine; ``uri`` and ``searched`` (the folders looked in)
    let the caller say where it looked (a model:// from Gazebo's online database, for example)."""

    def __init__(self, uri, searched, message):
        MeshError.__init__(self, message)
        self.uri = uri
        self.searched = list(searched)


#: Gazebo's download cache of its online model database: searched last, as Gazebo does
HOME_MODELS = os.path.join("~", ".gazebo", "models")


def model_dirs(exported=()):
    """Gazebo's model path, the one rule for ``model://``: GAZEBO_MODEL_PATH, then the
    ``gazebo_model_path`` folders that packages export (``exported``), then ~/.gazebo/models."""
    dirs = [d for d in os.environ.get("GAZEBO_MODEL_PATH", "").split(os.pathsep) if d]
    dirs += list(exported)
    dirs.append(os.path.expanduser(HOME_MODELS))
    out = []
    for d in dirs:
        if d not in out:
            out.append(d)
    return out


def find_model_uri(uri, dirs):
    """Absolute path of ``model://name/rest`` in the first of ``dirs`` that has it; raises
    ResourceNotFound naming the URI and the folders."""
    rel = uri[len("model://"):].lstrip("/")
    for d in dirs:
        path = os.path.join(d, rel)
        if rel and os.path.exists(path):
            return os.path.abspath(path)
    raise ResourceNotFound(uri, dirs, "%s: not found on this machine (looked in %s; Gazebo would download "
                                      "it from its online model database)" % (uri, ", ".join(dirs)))


def default_resolver(uri, rospack=None):
    """package:// through rospkg (no rospy), file:// and plain paths as they are, model:// through
    :func:`model_dirs`. Returns an absolute path or raises MeshError. ``rospack``: a
    rospkg.RosPack to ask (it keeps what it found: a new one crawls ROS_PACKAGE_PATH again, tens of
    milliseconds per URI on a long path), else a new one."""
    if uri.startswith("package://"):
        rest = uri[len("package://"):]
        pkg, _, rel = rest.partition("/")
        try:
            import rospkg
            base = (rospack or rospkg.RosPack()).get_path(pkg)
        except ImportError:
            raise MeshError("rospkg is not available to resolve '%s'" % uri)
        except Exception as e:  # rospkg.ResourceNotFound and friends
            raise MeshError("ROS package '%s' not found (%s): is the workspace sourced?"
                            % (pkg, type(e).__name__))
        return os.path.join(base, rel)
    if uri.startswith("file://"):
        return uri[len("file://"):]
    if uri.startswith("model://"):
        return find_model_uri(uri, model_dirs())
    return uri


# ---- readers ------------------------------------------------------------------------------------
def load_mesh(path):
    ext = os.path.splitext(path)[1].lower()
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise MeshError("cannot read mesh file '%s': %s" % (path, e.strerror or e))
    if ext == ".stl":
        verts, tris = _read_stl(data, path)
    elif ext == ".obj":
        verts, tris = _read_obj(data, path)
    elif ext == ".dae":
        verts, tris = _read_dae(data, path)
    else:
        raise MeshError("mesh '%s': unsupported format '%s' (STL, OBJ and DAE are supported)"
                        % (path, ext or "no extension"))
    if not tris:
        raise MeshError("mesh '%s' has no triangles" % path)
    for v in verts:
        if not (math.isfinite(v[0]) and math.isfinite(v[1]) and math.isfinite(v[2])):
            raise MeshError("mesh '%s' has a non-finite vertex" % path)
    return verts, tris


def _read_stl(data, path):
    if len(data) >= 84:
        n = struct.unpack_from("<I", data, 80)[0]
        if len(data) == 84 + 50 * n:
            verts = []
            tris = []
            off = 84
            for i in range(n):
                v = struct.unpack_from("<9f", data, off + 12)
                verts.append(v[0:3])
                verts.append(v[3:6])
                verts.append(v[6:9])
                tris.append((3 * i, 3 * i + 1, 3 * i + 2))
                off += 50
            return verts, tris
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError:
        raise MeshError("STL '%s' is neither a valid binary STL (size mismatch) nor ASCII" % path)
    if not text.lstrip().startswith("solid"):
        raise MeshError("STL '%s' is neither a valid binary STL (size mismatch) nor ASCII" % path)
    verts = []
    for m in re.finditer(r"vertex\s+(\S+)\s+(\S+)\s+(\S+)", text):
        try:
            verts.append((float(m.group(1)), float(m.group(2)), float(m.group(3))))
        except ValueError:
            raise MeshError("ASCII STL '%s': bad vertex '%s'" % (path, m.group(0)))
    if len(verts) % 3:
        raise MeshError("ASCII STL '%s': vertex count %d is not a multiple of 3" % (path, len(verts)))
    return verts, [(i, i + 1, i + 2) for i in range(0, len(verts), 3)]


def _read_obj(data, path):
    verts = []
    tris = []
    for lineno, line in enumerate(data.decode("utf-8", "replace").splitlines(), 1):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            try:
                verts.append((float(parts[1]), float(parts[2]), float(parts[3])))
            except (ValueError, IndexError):
                raise MeshError("OBJ '%s' line %d: bad vertex" % (path, lineno))
        elif parts[0] == "f":
            idx = []
            for p in parts[1:]:
                try:
                    k = int(p.split("/")[0])
                except ValueError:
                    raise MeshError("OBJ '%s' line %d: bad face index '%s'" % (path, lineno, p))
                k = k - 1 if k > 0 else len(verts) + k
                if not 0 <= k < len(verts):
                    raise MeshError("OBJ '%s' line %d: face index %s out of range" % (path, lineno, p))
                idx.append(k)
            for i in range(1, len(idx) - 1):
                tris.append((idx[0], idx[i], idx[i + 1]))
    return verts, tris


def _strip(tag):
    return tag.split("}", 1)[1] if tag.startswith("{") else tag


def _mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def _eye():
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def _node_matrix(node):
    m = _eye()
    for c in node:
        t = _strip(c.tag)
        numeric = t in ("matrix", "translate", "rotate", "scale")
        vals = [float(x) for x in (c.text or "").split()] if numeric else None
        if t == "matrix" and len(vals) == 16:
            m = _mat_mul(m, [vals[0:4], vals[4:8], vals[8:12], vals[12:16]])
        elif t == "translate" and len(vals) == 3:
            tm = _eye()
            tm[0][3], tm[1][3], tm[2][3] = vals
            m = _mat_mul(m, tm)
        elif t == "scale" and len(vals) == 3:
            sm = _eye()
            sm[0][0], sm[1][1], sm[2][2] = vals
            m = _mat_mul(m, sm)
        elif t == "rotate" and len(vals) == 4:
            x, y, z, a = vals
            n = math.sqrt(x * x + y * y + z * z) or 1.0
            x, y, z = x / n, y / n, z / n
            a = math.radians(a)
            c_, s = math.cos(a), math.sin(a)
            C = 1 - c_
            rm = [[c_ + x * x * C, x * y * C - z * s, x * z * C + y * s, 0.0],
                  [y * x * C + z * s, c_ + y * y * C, y * z * C - x * s, 0.0],
                  [z * x * C - y * s, z * y * C + x * s, c_ + z * z * C, 0.0],
                  [0.0, 0.0, 0.0, 1.0]]
            m = _mat_mul(m, rm)
    return m


def _read_dae(data, path):
    """Minimal COLLADA: <triangles> and <polylist>/<polygons> (fan-triangulated) of every
    <geometry>, placed by the <visual_scene> node transforms that instance them (each geometry
    once as-is if no scene instances it); <unit meter> is applied. <up_axis> is ignored, as
    Gazebo classic's COLLADA loader and RViz do (RViz drops the root transform in which Assimp
    puts the up-axis rotation): a Y_UP file modelled along z stands on z, as it does there."""
    try:
        root = ET.fromstring(data)
    except ET.ParseError as e:
        raise MeshError("DAE '%s' is not valid XML: %s" % (path, e))
    unit = 1.0
    for el in root.iter():
        t = _strip(el.tag)
        if t == "unit" and el.get("meter"):
            try:
                unit = float(el.get("meter"))
            except ValueError:
                pass
    geoms = {}
    for g in root.iter():
        if _strip(g.tag) != "geometry":
            continue
        gid = g.get("id", "")
        sources = {}
        vertices_src = {}
        tris = []
        mesh = None
        for c in g:
            if _strip(c.tag) == "mesh":
                mesh = c
        if mesh is None:
            continue
        for c in mesh:
            t = _strip(c.tag)
            if t == "source":
                fa = None
                stride = 3
                for e in c.iter():
                    et = _strip(e.tag)
                    if et == "float_array":
                        fa = e
                    elif et == "accessor" and e.get("stride"):
                        stride = int(e.get("stride"))
                if fa is not None:
                    try:
                        vals = [float(x) for x in (fa.text or "").split()]
                    except ValueError:
                        raise MeshError("DAE '%s': bad float_array in source '%s'" % (path, c.get("id")))
                    sources[c.get("id")] = [tuple(vals[i:i + 3]) for i in range(0, len(vals) - 2, stride)]
            elif t == "vertices":
                for inp in c:
                    if _strip(inp.tag) == "input" and inp.get("semantic") == "POSITION":
                        vertices_src[c.get("id")] = inp.get("source", "").lstrip("#")
        for c in mesh:
            t = _strip(c.tag)
            if t not in ("triangles", "polylist", "polygons"):
                continue
            inputs = [i for i in c if _strip(i.tag) == "input"]
            stride = max(int(i.get("offset", 0)) for i in inputs) + 1 if inputs else 1
            voff = None
            vsrc = None
            for i in inputs:
                if i.get("semantic") == "VERTEX":
                    voff = int(i.get("offset", 0))
                    vsrc = vertices_src.get(i.get("source", "").lstrip("#"))
            if voff is None or vsrc not in sources:
                continue
            ps = [p for p in c if _strip(p.tag) == "p"]
            vc = [p for p in c if _strip(p.tag) == "vcount"]
            counts = [int(x) for x in vc[0].text.split()] if vc else None
            for p in ps:
                idx = [int(x) for x in (p.text or "").split()]
                vidx = idx[voff::stride]
                if t == "triangles":
                    polys = [vidx[i:i + 3] for i in range(0, len(vidx) - 2, 3)]
                elif t == "polygons":
                    polys = [vidx]
                else:
                    polys = []
                    k = 0
                    for n in counts or []:
                        polys.append(vidx[k:k + n])
                        k += n
                for poly in polys:
                    for i in range(1, len(poly) - 1):
                        tris.append((vsrc, poly[0], poly[i], poly[i + 1]))
        if tris:
            geoms[gid] = (sources, tris)
    instanced = []

    def walk(node, m):
        m = _mat_mul(m, _node_matrix(node))
        for c in node:
            t = _strip(c.tag)
            if t == "instance_geometry":
                instanced.append((c.get("url", "").lstrip("#"), m))
            elif t == "node":
                walk(c, m)

    for vs in root.iter():
        if _strip(vs.tag) == "visual_scene":
            for node in vs:
                if _strip(node.tag) == "node":
                    walk(node, _eye())
    if not instanced:
        instanced = [(gid, _eye()) for gid in geoms]
    verts = []
    out = []
    for gid, m in instanced:
        if gid not in geoms:
            continue
        sources, tris = geoms[gid]
        cache = {}
        for src, a, b, c in tris:
            tri = []
            for k in (a, b, c):
                key = (src, k)
                if key not in cache:
                    pts = sources[src]
                    if not 0 <= k < len(pts):
                        raise MeshError("DAE '%s': vertex index %d out of range" % (path, k))
                    x, y, z = pts[k]
                    cache[key] = len(verts)
                    verts.append(tuple(unit * (m[r][0] * x + m[r][1] * y + m[r][2] * z + m[r][3])
                                       for r in range(3)))
                tri.append(cache[key])
            out.append(tuple(tri))
    return verts, out


def scaled(verts, scale):
    sx, sy, sz = scale
    out = [(x * sx, y * sy, z * sz) for x, y, z in verts]
    return out


def flip_if_mirrored(tris, scale):
    """A negative scale determinant mirrors the mesh: swap the winding to keep normals outward."""
    if scale[0] * scale[1] * scale[2] < 0:
        return [(a, c, b) for a, b, c in tris]
    return tris


def bounds(verts):
    xs = [v[0] for v in verts]
    ys = [v[1] for v in verts]
    zs = [v[2] for v in verts]
    return (min(xs), min(ys), min(zs)), (max(xs), max(ys), max(zs))

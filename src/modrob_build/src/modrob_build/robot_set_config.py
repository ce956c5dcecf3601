"""Robot sets from launch arguments or a YAML file (shared by the nodes and the launch files).

Launch arguments (strings; robots separated by ';'):
    orders:="59,3,55,63,57,5; 59,3,55,63,57,5"    bases:="0,0,1.02; 0.5,0,1.02"   (bases optional)
YAML file:
    robots:
      - {order: [59, 3, 55, 63, 57, 5], base: [0.0, 0.0, 1.02]}
      - {order: "59,3,55,63,57,5", base: [0.5, 0.0, 1.02, 3.14159]}
    gripper: true          # optional, as are grip_force and safety_distance
    grip_force: 3.0
    safety_distance: 0.8
"""
import yaml

from modrob_build.build import RobotSpec
from modrob_build.errors import BuildError, LayoutError


def _split(text):
    return [part.strip() for part in str(text).split(";") if part.strip()]


def _base_values(text, where):
    try:
        values = [float(v) for v in str(text).replace(",", " ").split()]
    except ValueError:
        raise LayoutError("%s: %r is not X,Y,Z or X,Y,Z,YAW" % (where, text))
    if len(values) not in (3, 4):
        raise LayoutError("%s: %r is not X,Y,Z or X,Y,Z,YAW" % (where, text))
    return values


def specs_from_strings(orders, bases=""):
    """RobotSpecs from the 'orders' and 'bases' launch-argument strings."""
    order_list = _split(orders)
    if not order_list:
        raise BuildError("no module order given: set orders:=\"59,3,55,63,57,5\" (robots separated "
                         "by ';') or a robots YAML file")
    base_list = _split(bases)
    if base_list and len(base_list) != len(order_list):
        raise LayoutError("%d bases for %d orders: give one X,Y,Z per robot (separated by ';') or none"
                          % (len(base_list), len(order_list)))
    base_values = [_base_values(b, "bases, robot %d" % i) for i, b in enumerate(base_list)]
    return [RobotSpec(o, base_values[i] if base_values else None) for i, o in enumerate(order_list)]


def load_robots_file(path):
    """(specs, options) from a robots YAML file; options has gripper/grip_force/safety_distance
    when the file sets them."""
    try:
        with open(path) as f:
            data = yaml.safe_load(f)
    except OSError as e:
        raise BuildError("cannot read the robots file %s: %s" % (path, e.strerror))
    except yaml.YAMLError as e:
        raise BuildError("robots file %s is not valid YAML: %s" % (path, e))
    if not isinstance(data, dict) or not isinstance(data.get("robots"), list) or not data["robots"]:
        raise BuildError("robots file %s: expected a mapping with a non-empty list 'robots' of "
                         "{order: [...], base: [x, y, z]}" % path)
    specs = []
    for i, entry in enumerate(data["robots"]):
        if not isinstance(entry, dict) or "order" not in entry:
            raise BuildError("robots file %s: robots[%d] needs an 'order'" % (path, i))
        base = entry.get("base")
        if base is not None:
            if isinstance(base, str):
                base = _base_values(base, "%s: robots[%d].base" % (path, i))
            elif not isinstance(base, (list, tuple)) or len(base) not in (3, 4):
                raise LayoutError("%s: robots[%d].base must be [x, y, z] or [x, y, z, yaw]" % (path, i))
        specs.append(RobotSpec(entry["order"], base))
    options = {k: data[k] for k in ("gripper", "grip_force", "safety_distance") if k in data}
    return specs, options

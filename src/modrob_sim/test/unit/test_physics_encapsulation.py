"""The World and its backends use Model, Link and Joint only through their physics-side
interface (physics/model.py), never through their private attributes: a change inside a model
class must not silently break the stepping. The backends are part of the World and may read the
World's own state."""
import ast
import os

import pytest

PHYSICS = os.path.join(os.path.dirname(__file__), "..", "..", "src", "modrob_sim", "physics")
#: names that stand for the World itself inside these modules; PyODE's own ``_id()``
WORLD_NAMES = {"self", "world", "w"}
ALLOWED_ATTRS = {"_id"}


def private_reads(path):
    tree = ast.parse(open(path).read(), path)
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Attribute):
            continue
        a = node.attr
        if not a.startswith("_") or a.startswith("__") or a in ALLOWED_ATTRS:
            continue
        owner = node.value
        if isinstance(owner, ast.Name) and (owner.id in WORLD_NAMES or owner.id.endswith("_mod")
                                            or owner.id == "odelib"):
            continue
        found.append("%s:%d %s.%s" % (os.path.basename(path), node.lineno,
                                      ast.unparse(owner), a))
    return found


@pytest.mark.parametrize("module", ["world.py", "backends.py", "gripper.py", "native_batch.py",
                                    "actuators.py"])
def test_no_private_attribute_of_another_object(module):
    assert private_reads(os.path.join(PHYSICS, module)) == []


def test_the_check_finds_a_private_read(tmp_path):
    p = tmp_path / "bad.py"
    p.write_text("def f(model):\n    return model._bodies\n")
    assert private_reads(str(p)) == ["bad.py:2 model._bodies"]

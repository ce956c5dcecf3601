"""No object of the physics core reads another object's private attributes: the World and its
backends use Model, Link and Joint only through their physics-side interface (physics/model.py),
the backends get what they share with the World handed over (world_parts.WorldParts) and never
see the World, and the builder uses the World's physics-side methods. A change inside a class
must not silently break the stepping. Only ``self`` may be read privately (an object's own
attributes); the builder constructs Model, Link and Joint and so sets theirs (it is checked for
the World's only)."""
import ast
import os

import pytest

PHYSICS = os.path.join(os.path.dirname(__file__), "..", "..", "src", "modrob_sim", "physics")
#: an object's own attributes; PyODE's own ``_id()``
OWN = {"self"}
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
        if isinstance(owner, ast.Name) and (owner.id in OWN or owner.id.endswith("_mod")
                                            or owner.id == "odelib"):
            continue
        found.append("%s:%d %s.%s" % (os.path.basename(path), node.lineno,
                                      ast.unparse(owner), a))
    return found


@pytest.mark.parametrize("module", ["world.py", "backends.py", "world_parts.py", "gripper.py",
                                    "contact_watch.py", "actuators.py"])
def test_no_private_attribute_of_another_object(module):
    assert private_reads(os.path.join(PHYSICS, module)) == []


def test_the_builder_reads_nothing_private_of_the_world():
    found = [r for r in private_reads(os.path.join(PHYSICS, "builder.py")) if " world." in r]
    assert found == []


def test_the_check_finds_a_private_read(tmp_path):
    p = tmp_path / "bad.py"
    p.write_text("def f(model):\n    return model._bodies\n")
    assert private_reads(str(p)) == ["bad.py:2 model._bodies"]

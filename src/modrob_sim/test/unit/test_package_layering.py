"""Tier 1: the generic simulator stays generic, and the workspace's packages depend one way.

modrob_sim must not name (in package.xml, Python imports, launch or test files) any package that
builds on it: the modular robot (modrob_build, modrob_motion, modrob_description), the
visualisation tools (modrob_viz) or a robot package. The whole package graph has no cycle.
"""
import glob
import importlib.util
import os
import re

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
SIM = os.path.join(SRC, "modrob_sim")
ABOVE = ("modrob_build", "modrob_motion", "modrob_description", "modrob_viz", "ptrz_camera",
         "katana_sim", "polaris_description")


def _graph_module():
    path = os.path.join(os.path.dirname(SRC), "scripts", "package_graph.py")
    spec = importlib.util.spec_from_file_location("package_graph", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_no_dependency_cycle():
    graph = _graph_module()
    pkgs = graph.read_packages(os.path.dirname(SRC))
    assert "modrob_sim" in pkgs and "modrob_kinematics" in pkgs
    assert graph.find_cycle(pkgs) is None


def test_simulator_declares_nothing_above_it():
    pkgs = _graph_module().read_packages(os.path.dirname(SRC))
    deps = pkgs["modrob_sim"]["run"] | pkgs["modrob_sim"]["test"]
    assert not deps & set(ABOVE), "modrob_sim depends on %s" % sorted(deps & set(ABOVE))


def test_simulator_sources_name_nothing_above_it():
    pattern = re.compile(r"\b(import|from)\s+(%s)\b|\$\(find (%s)\)|pkg=\"(%s)\""
                         % (("|".join(ABOVE),) * 3))
    offenders = []
    for path in glob.glob(os.path.join(SIM, "**", "*"), recursive=True):
        if os.path.isdir(path) or not path.endswith((".py", ".launch", ".test", ".xml", ".txt")) \
                and "/scripts/" not in path:
            continue
        with open(path, errors="replace") as f:
            for n, line in enumerate(f, 1):
                if pattern.search(line):
                    offenders.append("%s:%d: %s" % (os.path.relpath(path, SRC), n, line.strip()))
    assert not offenders, "modrob_sim names packages that build on it:\n" + "\n".join(offenders)

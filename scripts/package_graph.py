#!/usr/bin/env python3
"""Draw the workspace's package graph from every src/*/package.xml (graphviz ``dot``).

    python3 scripts/package_graph.py                     # docs/images/package_graph.{svg,png}
    python3 scripts/package_graph.py --check             # exit 1 if the graph has a cycle

An edge A -> B means A declares a dependency on B (build, exec, run or test); test-only edges
are dashed. Only the workspace's own packages are drawn. Lower rows are lower layers: a
package sits below everything that depends on it.
"""
import argparse
import glob
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUN_TAGS = ("depend", "build_depend", "exec_depend", "run_depend", "build_export_depend")


def read_packages(root=ROOT):
    """{name: {"run": set(deps), "test": set(deps), "description": text}} of src/*/package.xml."""
    pkgs = {}
    for path in sorted(glob.glob(os.path.join(root, "src", "*", "package.xml"))):
        xml = ET.parse(path).getroot()
        name = xml.findtext("name").strip()
        pkgs[name] = {"run": {e.text.strip() for tag in RUN_TAGS for e in xml.findall(tag)},
                      "test": {e.text.strip() for e in xml.findall("test_depend")},
                      "description": " ".join((xml.findtext("description") or "").split())}
    for info in pkgs.values():  # keep the workspace's own packages only
        info["run"] &= set(pkgs)
        info["test"] = (info["test"] & set(pkgs)) - info["run"]
    return pkgs


def find_cycle(pkgs, kinds=("run", "test")):
    """A list of package names forming a dependency cycle, or None."""
    state, stack = {}, []

    def visit(n):
        state[n] = 1
        stack.append(n)
        for d in sorted(set().union(*(pkgs[n][k] for k in kinds))):
            if state.get(d) == 1:
                return stack[stack.index(d):] + [d]
            if d not in state:
                found = visit(d)
                if found:
                    return found
        stack.pop()
        state[n] = 2
        return None

    for n in sorted(pkgs):
        if n not in state:
            found = visit(n)
            if found:
                return found
    return None


def levels(pkgs):
    """Layer of each package: 0 for packages with no workspace dependency, else 1 + max(deps)."""
    memo = {}

    def level(n):
        if n not in memo:
            deps = pkgs[n]["run"] | pkgs[n]["test"]
            memo[n] = 1 + max((level(d) for d in deps), default=-1)
        return memo[n]
    return {n: level(n) for n in pkgs}


def dot_source(pkgs):
    lv = levels(pkgs)
    lines = ["digraph packages {",
             '  rankdir=BT; node [shape=box, style="rounded,filled", fillcolor="#eef3fb",'
             ' fontname="Helvetica"]; edge [color="#555555"];']
    for level in sorted(set(lv.values())):
        names = " ".join('"%s"' % n for n in sorted(pkgs) if lv[n] == level)
        lines.append("  { rank=same; %s }" % names)
    for n in sorted(pkgs):
        for d in sorted(pkgs[n]["run"]):
            lines.append('  "%s" -> "%s";' % (n, d))
        for d in sorted(pkgs[n]["test"]):
            lines.append('  "%s" -> "%s" [style=dashed, label="test"];' % (n, d))
    lines.append("}")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "images", "package_graph"),
                    help="output path without extension (writes .dot, .svg and .png)")
    ap.add_argument("--check", action="store_true", help="only check that there is no cycle")
    args = ap.parse_args(argv)
    pkgs = read_packages()
    cycle = find_cycle(pkgs)
    if cycle:
        print("package dependency cycle: %s" % " -> ".join(cycle), file=sys.stderr)
        return 1
    if args.check:
        print("%d packages, no dependency cycle" % len(pkgs))
        return 0
    src = dot_source(pkgs)
    with open(args.out + ".dot", "w") as f:
        f.write(src)
    for fmt in ("svg", "png"):
        subprocess.run(["dot", "-T" + fmt, "-Gdpi=80", "-o", "%s.%s" % (args.out, fmt), args.out + ".dot"],
                       check=True)
    print("wrote %s.{dot,svg,png} (%d packages)" % (args.out, len(pkgs)))
    return 0


if __name__ == "__main__":
    sys.exit(main())

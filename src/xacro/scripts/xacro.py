#!/usr/bin/env python3
"""`$(find xacro)/xacro`: run the pinned PyPI xacro (the ROS 1 xacro 1.13) with these arguments.

roslaunch runs this file as an executable; it hands over to the `xacro` Python module that
requirements.txt installs into the workspace's virtual environment."""
import os
import sys

# Running this script puts its folder (or catkin's relay folder, devel/lib/xacro) first on
# sys.path, where `import xacro` would find the script `xacro.py` instead of the xacro module:
# leave out every folder that holds such a file but no xacro package.
_here = os.path.dirname(os.path.realpath(__file__))
sys.path[:] = [p for p in sys.path
               if not (os.path.isfile(os.path.join(p or os.curdir, "xacro.py"))
                       and not os.path.isdir(os.path.join(p or os.curdir, "xacro")))]

try:
    import xacro
except ImportError:
    # started by a python3 that is not the workspace's (a shell without scripts/env.sh): use the
    # workspace's virtual environment when this script sits in a source tree
    _venv = os.path.join(_here, "..", "..", "..", ".venv", "bin", "python3")
    if os.path.exists(_venv) and os.path.realpath(sys.executable) != os.path.realpath(_venv):
        os.execv(_venv, [_venv, os.path.realpath(__file__)] + sys.argv[1:])
    sys.stderr.write("xacro: the PyPI package xacro==1.13.3 is not installed for %s. Run 'make setup' "
                     "in the workspace, then 'source scripts/env.sh' (it puts the workspace's .venv "
                     "first on PATH).\n" % sys.executable)
    sys.exit(2)

if __name__ == "__main__":
    sys.argv[0] = "xacro"
    xacro.main()

# Generated-by-hand catkin python setup: the library lives in src/modrob_viz/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["modrob_viz", "modrob_viz.ros", "modrob_viz.render"],
                                 package_dir={"": "src"}))

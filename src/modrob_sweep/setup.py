# catkin python setup: the library lives in src/modrob_sweep/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["modrob_sweep"], package_dir={"": "src"}))

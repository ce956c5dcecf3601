# catkin python setup: the library lives in src/twist_mux/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["twist_mux"], package_dir={"": "src"}))

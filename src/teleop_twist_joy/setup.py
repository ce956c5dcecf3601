# catkin python setup: the library lives in src/teleop_twist_joy/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["teleop_twist_joy"], package_dir={"": "src"}))

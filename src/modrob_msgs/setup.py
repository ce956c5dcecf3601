# catkin python setup: the hand-written helpers live in src/modrob_msgs/ (the generated message
# modules, modrob_msgs.msg, are added to the same package by catkin in the devel space).
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["modrob_msgs"], package_dir={"": "src"}))

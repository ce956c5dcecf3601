# catkin python setup: the library lives in src/keyboard_teleop/ (not named like the package: the
# script teleop_twist_keyboard.py would shadow it).
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["keyboard_teleop"], package_dir={"": "src"}))

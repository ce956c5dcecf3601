# catkin python setup: the library lives in src/robot_localization/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["robot_localization"], package_dir={"": "src"}))

# catkin python setup: the library lives in src/interactive_marker_twist_server/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["interactive_marker_twist_server"], package_dir={"": "src"}))

# catkin python setup: the library lives in src/xacro/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["xacro"], package_dir={"": "src"}))

# catkin python setup: the library lives in src/joy/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["joy"], package_dir={"": "src"}))

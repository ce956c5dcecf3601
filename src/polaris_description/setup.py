# Generated-by-hand catkin python setup: the library lives in src/polaris_description/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["polaris_description"], package_dir={"": "src"}))

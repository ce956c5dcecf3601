# catkin python setup: the library lives in src/kdl_parser_py/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["kdl_parser_py"], package_dir={"": "src"}))

# catkin python setup: the library lives in src/franka_sim/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["franka_sim"], package_dir={"": "src"}))

# catkin python setup: the library lives in src/modrob_kinematics/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["modrob_kinematics"], package_dir={"": "src"}))

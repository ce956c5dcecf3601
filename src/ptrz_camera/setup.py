# catkin python setup: the library lives in src/ptrz_camera/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["ptrz_camera", "ptrz_camera.ros"], package_dir={"": "src"}))

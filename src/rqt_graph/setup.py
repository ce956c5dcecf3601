# catkin python setup: the library lives in src/rqt_graph/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["rqt_graph"], package_dir={"": "src"}))

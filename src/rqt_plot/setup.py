# catkin python setup: the library lives in src/rqt_plot/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["rqt_plot"], package_dir={"": "src"}))

# catkin python setup: the library lives in src/modrob_motion/.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["modrob_motion", "modrob_motion.bulbs_and_slides"],
                                 package_dir={"": "src"}))

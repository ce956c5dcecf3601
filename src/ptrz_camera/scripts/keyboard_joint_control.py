#!/usr/bin/env python3
"""Seed 002's keyboard teleop: rosrun ptrz_camera keyboard_joint_control.py [_ns:=/ptrz2]"""
import sys

from ptrz_camera.ros.teleop import main

if __name__ == "__main__":
    sys.exit(main())

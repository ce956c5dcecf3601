#!/usr/bin/env python3
"""Seed 002's scanner: rosrun ptrz_camera scanner_joint_control.py [_joints:=tilt] [_ns:=/ptrz2]"""
import sys

from ptrz_camera.ros.scanner_node import main

if __name__ == "__main__":
    sys.exit(main())

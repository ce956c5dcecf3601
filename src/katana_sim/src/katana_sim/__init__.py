"""Katana 450 arm simulation: laser, detection, IK, pick-and-stack (seed 001)."""

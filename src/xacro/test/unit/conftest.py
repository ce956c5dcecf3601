"""Lets the tests import their helper module beside them (pytest runs with --import-mode=importlib)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

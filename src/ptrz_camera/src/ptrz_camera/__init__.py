"""Pan/tilt/roll/zoom camera digital twin (seed 002)."""

"""Known paths of the tracked ball on the floor (pure functions of time)."""
import math


class FigureEight(object):
    """A figure eight (Lissajous 1:2) centred on the field: x = cx + ax sin(w t),
    y = cy + ay sin(2 w t), one loop per ``period`` seconds."""

    def __init__(self, cx=3.5, cy=0.0, ax=2.0, ay=1.2, period=30.0):
        self.cx, self.cy, self.ax, self.ay = cx, cy, ax, ay
        self.w = 2.0 * math.pi / period

    def position(self, t):
        return (self.cx + self.ax * math.sin(self.w * t), self.cy + self.ay * math.sin(2.0 * self.w * t))

    def velocity(self, t):
        return (self.ax * self.w * math.cos(self.w * t), 2.0 * self.ay * self.w * math.cos(2.0 * self.w * t))

"""teleop_twist_keyboard's key map and what a key press does, pure.

Moving (x, y, z, yaw as -1/0/1, times the current speed or turn):

    u    i    o        U    I    O     (shift: holonomic, strafing)
    j    k    l        J    K    L
    m    ,    .        M    <    >     t: up (+z), b: down (-z), anything else: stop

q/z: speed and turn x1.1 / x0.9; w/x: speed only; e/c: turn only (capped at the limits).
"""

MOVE = {
    "i": (1, 0, 0, 0), "o": (1, 0, 0, -1), "j": (0, 0, 0, 1), "l": (0, 0, 0, -1),
    "u": (1, 0, 0, 1), ",": (-1, 0, 0, 0), ".": (-1, 0, 0, 1), "m": (-1, 0, 0, -1),
    "O": (1, -1, 0, 0), "I": (1, 0, 0, 0), "J": (0, 1, 0, 0), "L": (0, -1, 0, 0),
    "U": (1, 1, 0, 0), "<": (-1, 0, 0, 0), ">": (-1, -1, 0, 0), "M": (-1, 1, 0, 0),
    "t": (0, 0, 1, 0), "b": (0, 0, -1, 0),
}
SPEED = {"q": (1.1, 1.1), "z": (0.9, 0.9), "w": (1.1, 1.0), "x": (0.9, 1.0), "e": (1.0, 1.1), "c": (1.0, 0.9)}
CTRL_C = "\x03"

HELP = """
Reading from the keyboard and publishing to Twist!
---------------------------
Moving around:
   u    i    o
   j    k    l
   m    ,    .

For holonomic mode (strafing), hold down the shift key:
---------------------------
   U    I    O
   J    K    L
   M    <    >

t : up (+z)
b : down (-z)

anything else : stop

q/z : increase/decrease max speeds by 10%
w/x : increase/decrease only linear speed by 10%
e/c : increase/decrease only angular speed by 10%

CTRL-C to quit
"""


class KeyTeleop(object):
    """The state a key changes. ``press(key)`` returns (twist or None, lines to print, quit);
    a twist is (linear x, y, z, angular z). ``key`` '' means no key within the key timeout."""

    def __init__(self, speed=0.5, turn=1.0, speed_limit=1000.0, turn_limit=1000.0):
        self.speed, self.turn = float(speed), float(turn)
        self.speed_limit, self.turn_limit = float(speed_limit), float(turn_limit)
        self.move = (0, 0, 0, 0)
        self._presses = 0

    def twist(self):
        x, y, z, th = self.move
        return (x * self.speed, y * self.speed, z * self.speed, th * self.turn)

    def status(self):
        return "currently:\tspeed %s\tturn %s " % (self.speed, self.turn)

    def press(self, key):
        lines = []
        if key in MOVE:
            self.move = MOVE[key]
        elif key in SPEED:
            fs, ft = SPEED[key]
            self.speed = min(self.speed_limit, self.speed * fs)
            self.turn = min(self.turn_limit, self.turn * ft)
            if self.speed == self.speed_limit:
                lines.append("Linear speed limit reached!")
            if self.turn == self.turn_limit:
                lines.append("Angular speed limit reached!")
            lines.append(self.status())
            if self._presses == 14:
                lines.append(HELP)
            self._presses = (self._presses + 1) % 15
        else:
            if key == "" and self.move == (0, 0, 0, 0):
                return None, lines, False          # timed out while standing: nothing to send
            self.move = (0, 0, 0, 0)
            if key == CTRL_C:
                return self.twist(), lines, True
        return self.twist(), lines, False

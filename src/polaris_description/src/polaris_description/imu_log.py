"""The IMU logger's pure part (the seed's write_to_file.py role): one CSV row per message."""
import csv

COLUMNS = ("stamp", "frame_id", "orientation_x", "orientation_y", "orientation_z", "orientation_w",
           "angular_velocity_x", "angular_velocity_y", "angular_velocity_z",
           "linear_acceleration_x", "linear_acceleration_y", "linear_acceleration_z")


class ImuCsvWriter(object):
    """Write rows to an open text file; ``row(...)`` takes the values in COLUMNS order."""

    def __init__(self, stream):
        self.stream = stream
        self.writer = csv.writer(stream)
        self.writer.writerow(COLUMNS)
        self.rows = 0

    def row(self, stamp, frame_id, orientation, angular_velocity, linear_acceleration):
        values = tuple(orientation) + tuple(angular_velocity) + tuple(linear_acceleration)
        self.writer.writerow(["%.6f" % stamp, frame_id] + ["%.9g" % v for v in values])
        self.rows += 1


def read_rows(path):
    """Rows of a logged CSV as dicts of floats (frame_id kept as text)."""
    with open(path) as f:
        out = []
        for r in csv.DictReader(f):
            out.append({k: (v if k == "frame_id" else float(v)) for k, v in r.items()})
        return out

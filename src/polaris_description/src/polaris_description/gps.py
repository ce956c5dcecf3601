"""hector_gazebo_ros_gps's flat-earth conversion and its inverse (pure).

lat = lat0 + (cos h x + sin h y) / R_north, lon = lon0 - (-sin h x + cos h y) / R_east (degrees,
R in metres per degree from the WGS84 radii at lat0), alt = alt0 + z; x, y, z in the world frame.
"""
import math

EQUATORIAL_RADIUS = 6378137.0
FLATTENING = 1.0 / 298.257223563
REFERENCE = (49.9, 8.9, 0.0, 0.0)   # latitude, longitude, heading (deg), altitude: hector's defaults


def radii(lat0_deg):
    """(R_north, R_east) in metres per degree at the reference latitude."""
    e2 = 2.0 * FLATTENING - FLATTENING ** 2
    s = math.sin(math.radians(lat0_deg))
    rn = EQUATORIAL_RADIUS * (1.0 - e2) / (1.0 - e2 * s * s) ** 1.5
    re = EQUATORIAL_RADIUS / math.sqrt(1.0 - e2 * s * s) * math.cos(math.radians(lat0_deg))
    return math.radians(rn), math.radians(re)


def to_fix(x, y, z, reference=REFERENCE):
    lat0, lon0, heading, alt0 = reference
    rn, re = radii(lat0)
    h = math.radians(heading)
    return (lat0 + (math.cos(h) * x + math.sin(h) * y) / rn,
            lon0 - (-math.sin(h) * x + math.cos(h) * y) / re,
            alt0 + z)


def from_fix(lat, lon, alt, reference=REFERENCE):
    """World position (x, y, z) of a fix: the inverse of :func:`to_fix`."""
    lat0, lon0, heading, alt0 = reference
    rn, re = radii(lat0)
    h = math.radians(heading)
    a = (lat - lat0) * rn             # cos h x + sin h y
    b = -(lon - lon0) * re            # -sin h x + cos h y
    return (math.cos(h) * a - math.sin(h) * b, math.sin(h) * a + math.cos(h) * b, alt - alt0)

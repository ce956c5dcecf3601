"""Recompute the derived columns of Modules.csv (com_*_z, i**_in, i**_out) from the shapes.

Comment lines and column order are kept; only the derived cells change.
"""
import csv
import io

from modrob_build.module_database import load_database

DERIVED = {"in": ("com_in_z", "ixx_in", "iyy_in", "izz_in"),
           "out": ("com_out_z", "ixx_out", "iyy_out", "izz_out")}


def _fmt(x):
    return "%.6g" % x


def filled_text(path):
    """The text of the database at `path` with the derived columns recomputed."""
    db = load_database(path)
    with open(path, newline="") as f:
        lines = f.read().splitlines()
    out, header = [], None
    for line in lines:
        if not line.strip() or line.lstrip().startswith("#"):
            out.append(line)
            continue
        cells = next(csv.reader([line]))
        if header is None:
            header = [c.strip() for c in cells]
            out.append(line)
            continue
        row = dict(zip(header, cells))
        module = db[int(row["id"])]
        props = module.derived_mass_properties()
        for role, cols in (("body", DERIVED["in"]), ("housing", DERIVED["in"]),
                           ("output", DERIVED["out"])):
            if role in props:
                _, com_z, inertia = props[role]
                for col, value in zip(cols, (com_z,) + tuple(inertia)):
                    row[col] = _fmt(value)
        buf = io.StringIO()
        csv.writer(buf, lineterminator="").writerow([row[h] for h in header])
        out.append(buf.getvalue())
    return "\n".join(out) + "\n"

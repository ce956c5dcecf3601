"""Modules.csv: every ID the seeds use, derived columns consistent, bad rows named precisely."""
import os
import shutil

import pytest

from modrob_build.errors import DatabaseError
from modrob_build.inertia_fill import filled_text
from modrob_build.module_database import default_database_path, load_database
from modrob_build import shapes

SPEC_KINDS = {59: "base", 3: "link", 4: "link", 5: "link", 55: "joint_inline", 56: "joint_inline",
              57: "joint_inline", 63: "joint_elbow", 64: "joint_elbow", 66: "joint_elbow",
              67: "joint_elbow"}


@pytest.fixture(scope="module")
def db():
    return load_database()


def test_spec_ids_and_kinds(db):
    for module_id, kind in SPEC_KINDS.items():
        assert db[module_id].kind == kind, module_id


def test_tubes_increase_in_length(db):
    assert db[3].length < db[4].length < db[5].length


def test_joint_modules_have_harmonic_drive_and_axes(db):
    for module_id, kind in SPEC_KINDS.items():
        m = db[module_id]
        if m.is_joint:
            assert m.reduction == 160
            assert (m.axis == "z") == (kind == "joint_inline")
            assert m.effort > 0 and m.velocity > 0 and m.lower < 0 < m.upper


def test_colours_match_gazebo_materials(db):
    for m in db.modules.values():
        expected = "Gazebo/Blue" if m.is_joint else "Gazebo/DarkGrey"
        assert m.gazebo_material == expected, m.id
        if m.is_joint:
            assert m.rgba[2] > 0.5 and m.rgba[0] < 0.2
        else:
            assert max(m.rgba[:3]) < 0.3


def test_derived_columns_are_up_to_date():
    path = default_database_path()
    with open(path) as f:
        assert f.read() == filled_text(path), "run `rosrun modrob_build fill_module_inertia`"


def test_inertias_are_physical_and_tubes_match_formula(db):
    for m in db.modules.values():
        for body in m.bodies():
            assert shapes.satisfies_triangle_inequality(body.inertia)
    tube = db[5]
    ixx, _, izz = shapes.tube_inertia(tube.mass_in, tube.radius, tube.radius - tube.wall, tube.length)
    assert tube.ixx_in == pytest.approx(ixx, rel=1e-5) and tube.izz_in == pytest.approx(izz, rel=1e-5)


def test_fill_recomputes_wrong_inertia(tmp_path):
    path = tmp_path / "Modules.csv"
    text = open(default_database_path()).read().replace(",0.0073,0.0073,0.0096,", ",1,1,1,")
    path.write_text(text)
    assert ",0.0073,0.0073,0.0096," in filled_text(str(path))


def _broken(tmp_path, old, new):
    src = default_database_path()
    path = tmp_path / "Modules.csv"
    shutil.copy(src, path)
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))
    lines = text.splitlines()
    line_no = next(i for i, line in enumerate(lines, start=1) if old in line)
    return str(path), line_no


@pytest.mark.parametrize("old,new,column,words", [
    ("55,inline_large,joint_inline,0.05,", "55,inline_large,joint_inline,abc,", "radius", "not a number"),
    ("4,tube_medium,link,", "4,tube_medium,tube,", "kind", "not one of"),
    ("56,inline_small,joint_inline,0.04,,0.10,0.065,z,", "56,inline_small,joint_inline,0.04,,0.10,0.065,q,",
     "axis", "not x, y or z"),
    ("3,tube_short,link,0.045,0.004,0.10,", "3,tube_short,link,0.045,0.004,-0.10,", "length", "> 0"),
    ("57,inline_medium,", "55,inline_medium,", "id", "already defined"),
    ("0.175 0.175 0.175 1,Gazebo/DarkGrey,base", "0.175 0.175 1,Gazebo/DarkGrey,base", "rgba", "RGBA"),
    (",160,0.41,0.8,0.8,0.0 0.0 0.8 1,Gazebo/Blue,inline", ",,0.41,0.8,0.8,0.0 0.0 0.8 1,Gazebo/Blue,inline",
     "reduction", "empty"),
])
def test_bad_row_names_file_line_and_column(tmp_path, old, new, column, words):
    path, line_no = _broken(tmp_path, old, new)
    with pytest.raises(DatabaseError) as err:
        load_database(path)
    msg = str(err.value)
    assert "%s:%d" % (path, line_no) in msg
    assert "'%s'" % column in msg
    assert words in msg


def test_missing_column_and_missing_file(tmp_path):
    path, _ = _broken(tmp_path, "mu1,mu2,", "mu1,")
    with pytest.raises(DatabaseError, match="lacks column.*mu2"):
        load_database(path)
    with pytest.raises(DatabaseError, match="cannot read"):
        load_database(os.path.join(str(tmp_path), "nope.csv"))


def test_short_row_is_refused(tmp_path):
    path, line_no = _broken(tmp_path, ",Gazebo/DarkGrey,base module", ",base module")
    with pytest.raises(DatabaseError, match=r":%d: \d+ cells" % line_no):
        load_database(path)

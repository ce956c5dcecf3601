"""modrob_description's files on their own (no modrob_build): the module database has the IDs the
seeds use, the gripper macro expands with xacro and gives a valid URDF, the committed URDFs parse."""
import csv
import os
import subprocess

PKG = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SPEC_KINDS = {59: "base", 3: "link", 4: "link", 5: "link", 55: "joint_inline", 56: "joint_inline",
              57: "joint_inline", 63: "joint_elbow", 64: "joint_elbow", 66: "joint_elbow",
              67: "joint_elbow"}


def test_modules_csv_has_the_seed_ids():
    with open(os.path.join(PKG, "config", "Modules.csv")) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    kinds = {int(r["id"]): r["kind"] for r in rows}
    for module_id, kind in SPEC_KINDS.items():
        assert kinds.get(module_id) == kind, module_id


def test_gripper_macro_expands_to_a_valid_urdf(tmp_path):
    wrapper = tmp_path / "g.urdf.xacro"
    wrapper.write_text(
        '<robot name="g" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<link name="world"/><xacro:include filename="%s/urdf/gripper.xacro"/>'
        '<xacro:modrob_gripper prefix="x_" parent="world" grip_force="5.0"/></robot>' % PKG)
    out = subprocess.run(["xacro", str(wrapper)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert 'effort="5.0"' in out.stdout and 'name="gripper_finger2_joint"' in out.stdout
    urdf = tmp_path / "g.urdf"
    urdf.write_text(out.stdout)
    check = subprocess.run(["check_urdf", str(urdf)], capture_output=True, text=True)
    assert check.returncode == 0, check.stdout + check.stderr
    assert "x_gripper_tcp" in check.stdout


def test_committed_urdfs_pass_check_urdf():
    for name in ("two_link_test.urdf", "modrob_4dof_demo.urdf"):
        out = subprocess.run(["check_urdf", os.path.join(PKG, "urdf", name)], capture_output=True, text=True)
        assert out.returncode == 0, name + out.stdout + out.stderr

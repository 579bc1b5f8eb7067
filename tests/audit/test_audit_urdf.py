"""The audit against example-robot-data's URDFs finds the base rotation found by hand.

tests/model/test_example_robot_data.py states T_erd_our = identity for ur3, ur5 and ur10 (tool = tool0;
each table's [base] is the URDF's base_link -> base turn) and panda (tool = panda_link8); the audit
must find the same from the URDFs alone, to 1e-9, find Rz(pi) for a UR table without its [base]
(the controller's DH base frame), and find a twist sign, the convention or the length unit when we
corrupt our table.
"""

from __future__ import annotations

import importlib.metadata
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from dh2urdf import ROBOTS, get_robot
from kin.audit import AuditError, audit_urdf
from kin.commands.audit import main

TOL = 1e-9
RZ_PI = np.diag([-1.0, -1.0, 1.0, 1.0])

#: robot -> (URDF inside example-robot-data's robots folder, frame, expected base B).
CASES = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_link8", np.eye(4)),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", "tool0", np.eye(4)),
    "ur3": ("ur_description/urdf/ur3_robot.urdf", "tool0", np.eye(4)),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0", np.eye(4)),
}


def erd_urdf(relative: str) -> Path:
    """Absolute path of an example-robot-data URDF (``robots/<relative>``)."""
    suffix = f"example-robot-data/robots/{relative}"
    for file in importlib.metadata.files("example-robot-data") or ():
        if str(file).endswith(suffix):
            return Path(str(file.locate()))
    raise FileNotFoundError(suffix)


@pytest.mark.parametrize("robot", sorted(CASES))
def test_finds_the_base_transform_of_example_robot_data(robot):
    """Table as written, base and tool identity (ur3, ur5, ur10, panda), to 1e-9."""
    relative, frame, base = CASES[robot]
    audit = audit_urdf(robot, erd_urdf(relative), frame)
    best = audit.best
    assert best.reading.changes == (), f"{robot=} {best.reading.label}"
    assert best.reproduced
    assert np.abs(best.fit.T_ref_base - base).max() < TOL, f"{robot=} {best.fit.T_ref_base}"
    assert np.abs(best.fit.T_tool_ref - np.eye(4)).max() < TOL, f"{robot=} {best.fit.T_tool_ref}"
    assert best.fit.position_residual_m < TOL and best.fit.rotation_residual_rad < 1e-10
    assert audit.reference.mapped_by == "name"


def corrupted_ur5(
    tmp_path: Path,
    *,
    row: int = 0,
    convention: str = "",
    millimeters: bool = False,
    degrees: bool = False,
):
    """ur5.toml with the twist of ``row`` negated, another convention, lengths in mm, or its
    radians labelled degrees."""
    text = get_robot("ur5").table_path.read_text(encoding="utf-8")
    head, *blocks = text.split("[[joints]]")
    if row:
        blocks[row - 1] = blocks[row - 1].replace("alpha = ", "alpha = -").replace("--", "")
    if convention:
        head = head.replace('convention = "standard"', f'convention = "{convention}"')
    if degrees:
        head = head.replace('angle_unit = "rad"', 'angle_unit = "deg"')
    if millimeters:
        for k, block in enumerate(blocks):
            lines = []
            for line in block.splitlines():
                key, _, value = line.partition(" = ")
                if key in ("a", "d"):
                    line = f"{key} = {float(value) * 1000.0!r}"
                lines.append(line)
            blocks[k] = "\n".join(lines) + "\n"
    path = tmp_path / "ur5_corrupted.toml"
    path.write_text("[[joints]]".join([head, *blocks]), encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("options", "expected"),
    [
        ({"row": 4}, "alpha4: -1.5708 -> 1.5708 rad"),
        ({"convention": "modified"}, "convention: modified -> standard"),
        ({"millimeters": True}, "length unit of the table: m -> mm"),
        ({"degrees": True}, "angle unit of the table: deg -> rad"),
    ],
)
def test_finds_a_corruption_of_our_ur5(tmp_path, options, expected):
    """A corrupted ur5 table: the best reading undoes it and gives the identity base again."""
    table = corrupted_ur5(tmp_path, **options)
    audit = audit_urdf(table, erd_urdf(CASES["ur5"][0]), "tool0")
    assert [c.text for c in audit.best.reading.changes] == [expected], audit.best.reading.label
    assert audit.best.reproduced
    # The reading re-reads the rows' angles, not [base]'s: its rpy z of pi read as pi deg turns
    # the table's base by pi^2/180 rad about z, and the fitted base takes that turn back.
    misread = math.pi * math.pi / 180.0 if options.get("degrees") else math.pi
    c, s = math.cos(math.pi - misread), math.sin(math.pi - misread)
    expected = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
    assert np.abs(audit.best.fit.T_ref_base - expected).max() < TOL, audit.best.fit.T_ref_base
    assert not next(s for s in audit.scores if not s.reading.changes).reproduced


def test_joints_matched_by_order_when_names_differ(tmp_path):
    """Our ur5 with other joint names still maps onto the URDF's joints, by order."""
    text = get_robot("ur5").table_path.read_text(encoding="utf-8")
    path = tmp_path / "renamed.toml"
    path.write_text(text.replace('name = "shoulder_', 'name = "my_shoulder_'), encoding="utf-8")
    audit = audit_urdf(path, erd_urdf(CASES["ur5"][0]), "tool0", pairs=False)
    assert audit.reference.mapped_by == "order"
    assert audit.best.reading.changes == () and audit.best.reproduced


def test_missing_frame_names_it():
    """A frame the URDF lacks: AuditError naming the frame and listing the URDF's frames."""
    with pytest.raises(AuditError, match=r"no frame 'tool9'; available frames: .*tool0"):
        audit_urdf("ur5", erd_urdf(CASES["ur5"][0]), "tool9")


def without_base(tmp_path: Path, robot: str) -> Path:
    """A shipped table with its [base] section dropped: its world is DH frame 0."""
    text = get_robot(robot).table_path.read_text(encoding="utf-8")
    text, count = re.subn(r"\n\[base\]\n(?:\w+ = .*\n)*", "\n", text)
    assert count == 1, f"{robot=} has no [base]"
    path = tmp_path / f"{robot}_no_base.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("robot", ["ur10", "ur3", "ur5"])
def test_finds_rz_pi_for_a_ur_table_in_the_controllers_frame(tmp_path, robot):
    """A UR table without its [base] (DH frame 0, the controller's base frame, as up to 0.3.0):
    the audit finds base Rz(pi) from base_link, tool identity, to 1e-9."""
    relative, frame, _ = CASES[robot]
    audit = audit_urdf(without_base(tmp_path, robot), erd_urdf(relative), frame)
    best = audit.best
    assert best.reading.changes == () and best.reproduced, f"{robot=} {best.reading.label}"
    assert np.abs(best.fit.T_ref_base - RZ_PI).max() < TOL, f"{robot=} {best.fit.T_ref_base}"
    assert np.abs(best.fit.T_tool_ref - np.eye(4)).max() < TOL, f"{robot=} {best.fit.T_tool_ref}"


def test_json_gives_base_and_tool_in_the_table_units(tmp_path, capsys):
    """--json on ur3 without its [base] (the controller's DH base frame): readings best first,
    base rpy (0, 0, +-pi) rad, residuals in SI."""
    table = str(without_base(tmp_path, "ur3"))
    code = main([table, "--urdf", str(erd_urdf(CASES["ur3"][0])), "--frame", "tool0", "--json"])
    assert code == 0
    record = json.loads(capsys.readouterr().out)
    best = record["readings"][0]
    assert best["changes"] == [] and best["reproduced"] is True
    assert np.allclose(best["base"]["xyz"], 0.0, atol=TOL)
    roll, pitch, yaw = best["base"]["rpy"]
    assert abs(roll) < TOL and abs(pitch) < TOL and abs(abs(yaw) - math.pi) < TOL
    assert best["position_residual_m"] < TOL
    assert record["joints_matched_by"] == "name" and record["frame"] == "tool0"


@pytest.mark.parametrize("robot", sorted(ROBOTS))
def test_each_table_matches_its_own_urdf(robot):
    """Every shipped table against its generated URDF: as written, B = E = identity."""
    audit = audit_urdf(robot, get_robot(robot).urdf_path, "tool", pairs=False)
    fit = audit.best.fit
    assert audit.best.reading.changes == (), f"{robot=} {audit.best.reading.label}"
    assert np.abs(fit.T_ref_base - np.eye(4)).max() < TOL, f"{robot=}"
    assert np.abs(fit.T_tool_ref - np.eye(4)).max() < TOL, f"{robot=}"
    assert fit.unique == (robot != "planar2"), f"{robot=} {fit.unique=}"


def test_fits_a_general_base_and_tool(tmp_path):
    """ur5 with another [base] and a [tool] (turned about every axis) as the reference URDF: the
    plain ur5 table (its own [base] B0) fits it with exactly those transforms (base B B0^-1)."""
    from dh2urdf import load_table, urdf_string
    from dh2urdf.transforms import xyz_rpy

    base_xyz, base_rpy = (0.1, -0.2, 0.3), (0.3, -0.2, 1.0)
    tool_xyz, tool_rpy = (0.01, 0.02, 0.15), (0.5, 0.1, -0.4)
    text = get_robot("ur5").table_path.read_text(encoding="utf-8")
    text = re.sub(r"\n\[base\]\n(?:\w+ = .*\n)*", "\n", text)
    text += f"\n[base]\nxyz = {list(base_xyz)}\nrpy = {list(base_rpy)}\n"
    text += f"\n[tool]\nxyz = {list(tool_xyz)}\nrpy = {list(tool_rpy)}\n"
    table_path = tmp_path / "ur5_mounted.toml"
    table_path.write_text(text, encoding="utf-8")
    urdf = tmp_path / "ur5_mounted.urdf"
    urdf.write_text(urdf_string(load_table(table_path)), encoding="utf-8")
    audit = audit_urdf("ur5", urdf, "tool")
    fit = audit.best.fit
    assert audit.best.reading.changes == () and fit.unique
    B0 = np.diag([-1.0, -1.0, 1.0, 1.0])  # ur5.toml's [base]: rpy (0, 0, pi)
    assert np.abs(fit.T_ref_base - xyz_rpy(base_xyz, base_rpy) @ np.linalg.inv(B0)).max() < TOL
    assert np.abs(fit.T_tool_ref - xyz_rpy(tool_xyz, tool_rpy)).max() < TOL


def test_finds_a_joint_that_turns_the_other_way(tmp_path):
    """Our ur5 URDF with wrist_1 turning about -z: the reading 'q4 reversed' fits it exactly."""
    text = get_robot("ur5").urdf_path.read_text(encoding="utf-8")
    head, tail = text.split('<joint name="wrist_1_joint"', 1)
    tail = tail.replace('<axis xyz="0.0 0.0 1.0"/>', '<axis xyz="0.0 0.0 -1.0"/>', 1)
    urdf = tmp_path / "ur5_reversed.urdf"
    urdf.write_text(head + '<joint name="wrist_1_joint"' + tail, encoding="utf-8")
    audit = audit_urdf("ur5", urdf, "tool")
    assert [c.kind for c in audit.best.reading.changes] == ["joint_sign"]
    assert audit.best.reading.changes[0].row == 4 and audit.best.reproduced


def test_continuous_joints(tmp_path):
    """A URDF whose joints are continuous (cos, sin configuration): the table as written fits."""
    text = get_robot("ur5").urdf_path.read_text(encoding="utf-8")
    urdf = tmp_path / "ur5_continuous.urdf"
    urdf.write_text(text.replace('type="revolute"', 'type="continuous"'), encoding="utf-8")
    audit = audit_urdf("ur5", urdf, "tool", pairs=False)
    assert audit.best.reading.changes == () and audit.best.reproduced
    assert all(audit.reference.continuous)


def test_readings_that_are_one_model_up_to_base_and_tool_are_grouped(capsys):
    """ur5 against example-robot-data's URDF: d1 sign, theta1 +-90 deg, d6 sign... reproduce
    only because the fitted base and tool absorb them: one line 'same model as rank 1', and
    each such reading's FK is the best one's with constant transforms (checked independently)."""
    from kin import batch_forward_kinematics
    from kin.audit.report import urdf_audit_text

    relative, frame, _ = CASES["ur5"]
    audit = audit_urdf("ur5", erd_urdf(relative), frame)
    best = audit.best
    assert best.reproduced and not best.reading.changes
    same = [s for s in audit.scores if s.same_as_best]
    labels = " ".join(s.reading.label for s in same)
    assert len(same) >= 8 and "d1: " in labels and "theta1: " in labels
    assert all(s.reproduced for s in same)
    assert not any(s.same_as_best for s in audit.scores if not s.reproduced)
    rng = np.random.default_rng(5)
    q = rng.uniform(-3, 3, size=(50, 6))
    for s in same[:5]:
        ours = batch_forward_kinematics(s.reading.table, q * s.reading.signs)
        first = batch_forward_kinematics(best.reading.table, q)
        # Through the reference: B_s T_s E_s = B_1 T_1 E_1 at every q.
        left = s.fit.T_ref_base @ ours @ s.fit.T_tool_ref
        right = best.fit.T_ref_base @ first @ best.fit.T_tool_ref
        assert np.abs(left - right).max() < 1e-6
    text = urdf_audit_text(audit)
    assert text.count("same model as rank 1 up to the base/tool transform") == 1

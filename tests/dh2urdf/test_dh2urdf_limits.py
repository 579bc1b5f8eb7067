"""Table bounds and link physics: overflowing lengths rejected, masses give cylinder inertials."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import numpy as np
import pytest
from lxml import etree

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10: the same parser as the package's
    import tomli as tomllib

from dh2urdf import TableError, parse_table
from dh2urdf.table_file import MAX_LENGTH
from dh2urdf.urdf_writer import cylinder_inertia, urdf_string
from dh2urdf.yourdfpy_model import build_urdf

TABLE = textwrap.dedent(
    """
    convention = "standard"
    length_unit = "mm"
    angle_unit = "deg"

    [[joints]]
    type = "revolute"
    a = 300.0
    alpha = 0.0
    d = 100.0
    theta = 0.0
    limits = [-90.0, 90.0]

    [[joints]]
    type = "prismatic"
    a = 0.0
    alpha = 0.0
    d = 0.0
    theta = 0.0
    limits = [0.0, 200.0]
    """
)


def table_with(row: int, **fields: object) -> dict:
    """The two-joint test table with ``fields`` set on joint row ``row`` (1-based)."""
    data = tomllib.loads(TABLE)
    data["joints"][row - 1].update(fields)
    return data


@pytest.mark.parametrize(
    ("row", "field", "value"),
    [
        (1, "a", 1e308),
        (1, "d", -1e308),
        (1, "a", 2e9),  # 2e9 mm = 2e6 m: above the bound once scaled
        (2, "limits", [0.0, 1e300]),
    ],
)
def test_overflowing_length_names_row_field_and_bound(row, field, value):
    """A length above 1e6 m (after unit scaling) is a TableError naming row, field and bound."""
    with pytest.raises(TableError) as info:
        parse_table(table_with(row, **{field: value}), "arm.toml")
    message = str(info.value)
    assert info.value.row == row and info.value.field == field, message
    assert message.startswith(f"arm.toml, joint row {row}, field '{field}'"), message
    assert "must be a finite length below 1e+06 m" in message, message


def test_length_at_the_bound_is_accepted_and_finite():
    """a = 1e6 m exactly loads, and every number of the URDF is finite."""
    data = table_with(1, a=MAX_LENGTH * 1000.0)  # mm
    text = urdf_string(parse_table(data))
    assert "nan" not in text and "inf" not in text


@pytest.mark.parametrize("key", ["xyz", "a"])
def test_overflowing_tool_offset_is_rejected(key):
    """[tool] xyz or DH-style a beyond the bound is a TableError naming the field."""
    data = tomllib.loads(TABLE)
    data["tool"] = {"xyz": [1e308, 0.0, 0.0]} if key == "xyz" else {"a": 1e308}
    with pytest.raises(TableError, match=rf"field 'tool\.{key}'.*finite length below"):
        parse_table(data, "arm.toml")


@pytest.mark.parametrize(
    ("field", "value"), [("mass", 0.0), ("mass", -1.0), ("mass", float("inf")), ("radius", 0.0)]
)
def test_bad_mass_or_radius_names_row_and_field(field, value):
    """Mass and radius must be positive and finite; the error names the row and the field."""
    with pytest.raises(TableError) as info:
        parse_table(table_with(2, **{field: value}), "arm.toml")
    assert (info.value.row, info.value.field) == (2, field), str(info.value)


def test_mass_gives_solid_cylinder_inertia_about_its_center():
    """Row 1 (a = 0.3 m, r = 0.02 m, 2 kg): I = diag(m(3r^2+L^2)/12, same, mr^2/2) at a/2."""
    mass, radius, length = 2.0, 0.02, 0.3
    table = parse_table(table_with(1, mass=mass, radius=radius * 1000.0))
    inertial = build_urdf(table).robot.links[2].inertial  # base_link, frame0, link1
    assert inertial.mass == mass
    np.testing.assert_allclose(inertial.origin[:3, 3], [length / 2, 0.0, 0.0], atol=1e-15)
    R = inertial.origin[:3, :3]
    in_link = R @ inertial.inertia @ R.T  # axis of the cylinder is the link's x
    side = mass * (3 * radius**2 + length**2) / 12
    np.testing.assert_allclose(
        in_link, np.diag([mass * radius**2 / 2, side, side]), rtol=1e-12, atol=1e-15
    )


def test_cylinder_inertia_closed_forms():
    """Solid cylinder and (zero length) solid sphere against their textbook formulas."""
    np.testing.assert_allclose(cylinder_inertia(3.0, 0.1, 0.5), np.diag([0.07, 0.07, 0.015]))
    np.testing.assert_allclose(cylinder_inertia(5.0, 0.2, 0.0), np.eye(3) * 0.08)


def test_radius_sizes_visual_and_collision_cylinders():
    """The row's radius [mm] is the cylinder radius [m] of the visual and the collision."""
    text = urdf_string(parse_table(table_with(1, radius=25.0)))
    root = etree.fromstring(text.encode())
    link = root.find("link[@name='link1']")
    radii = [float(c.get("radius")) for c in link.iter("cylinder") if c.get("length") == "0.3"]
    assert radii == [0.025, 0.025], radii
    assert link.find("collision") is not None


def test_placeholder_comment_only_without_masses():
    """Without masses the URDF says its inertials are placeholders; with all masses it does not."""
    note = "placeholders for visualization, not dynamics"
    assert note in urdf_string(parse_table(tomllib.loads(TABLE)))
    data = table_with(1, mass=1.0)
    data["joints"][1]["mass"] = 0.5
    text = urdf_string(parse_table(data))
    assert note not in text
    root = etree.fromstring(text.encode())
    assert root.find("link[@name='base_link']/inertial") is None  # KDL: no root inertia


def test_mujoco_loads_the_urdf_with_every_frame():
    """MuJoCo reads the compiler element of the URDF: frame0..2, link1..2 and tool are bodies."""
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_string(urdf_string(parse_table(tomllib.loads(TABLE))))
    names = {model.body(i).name for i in range(model.nbody)}
    assert {"base_link", "frame0", "frame1", "frame2", "link1", "link2", "tool"} <= names


def test_overflow_table_on_the_command_line_writes_nothing(tmp_path):
    """dh2urdf on a = 1e308: exit 2, one stderr line naming row and field, no file."""
    data = TABLE.replace("a = 300.0", "a = 1e308")
    table = tmp_path / "big.toml"
    table.write_text(data)
    out = tmp_path / "big.urdf"
    run = subprocess.run(
        [sys.executable, "-m", "dh2urdf", str(table), "-o", str(out)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 2, run.stderr
    assert len(run.stderr.splitlines()) == 1 and "Traceback" not in run.stderr
    assert "joint row 1, field 'a'" in run.stderr
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["big.toml"]


def test_all_masses_make_the_frames_massless_in_mujoco():
    """With every row's mass given, MuJoCo's bodies weigh exactly the table's masses (3 kg)."""
    mujoco = pytest.importorskip("mujoco")
    data = table_with(1, mass=2.0)
    data["joints"][1]["mass"] = 1.0
    model = mujoco.MjModel.from_xml_string(urdf_string(parse_table(data)))
    masses = {model.body(i).name: float(model.body_mass[i]) for i in range(model.nbody)}
    assert masses["link1"] == 2.0 and masses["link2"] == 1.0, masses
    assert sum(masses.values()) == 3.0, masses

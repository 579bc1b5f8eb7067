"""A DH table's body: segment radii, capsule ends, housings, the default note, and the shipped
tables' housings against the makers' collision meshes (scripts/check_dh_volumes.py)."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import call
from support.scripts_helper import load_script

from dh2urdf import TableError, parse_table
from dh2urdf.link_volumes import default_radius_note
from dh2urdf.urdf_writer import urdf_string
from kin import load_robot
from kin.commands import check
from kin.robot_model import robot_from_table

#: One standard row (mm, deg): a = 300 along x1, d = 100 along z0, alpha = 90.
ROW = {"type": "revolute", "a": 300.0, "alpha": 90.0, "d": 100.0, "theta": 0.0, "limits": [-90, 90]}
#: Configurations per arm in the quick comparison with the makers' meshes.
QUICK = 500


def _table(**fields: object):
    units = {"convention": "standard", "length_unit": "mm", "angle_unit": "deg"}
    return parse_table({**units, "joints": [{**ROW, **fields}]})


def _collisions(table) -> dict[str, tuple[str, dict[str, str]]]:
    """Collision name -> (link, geometry attributes) of the table's URDF."""
    out = {}
    for link in ET.fromstring(urdf_string(table)).iter("link"):
        for collision in link.findall("collision"):
            shape = collision.find("geometry")[0]
            out[collision.get("name")] = (link.get("name"), {"tag": shape.tag, **shape.attrib})
    return out


def test_radius_a_and_radius_d_size_their_segments_and_close_the_joint():
    """radius_a 40 mm and radius_d 20 mm: the a cylinder 0.04 m, the d cylinder 0.02 m, each
    closed by a sphere of its radius at the joint where they meet; the chain's ends stay flat."""
    shapes = _collisions(_table(radius_a=40.0, radius_d=20.0))
    assert shapes["a1_collision"] == (
        "link1",
        {"tag": "cylinder", "radius": "0.04", "length": "0.3"},
    )
    assert shapes["d1_collision"] == (
        "frame0",
        {"tag": "cylinder", "radius": "0.02", "length": "0.1"},
    )
    assert shapes["d1_end_collision"][1] == {"tag": "sphere", "radius": "0.02"}
    assert shapes["a1_start_collision"][1] == {"tag": "sphere", "radius": "0.04"}
    assert "d1_start_collision" not in shapes and "a1_end_collision" not in shapes


def test_radius_sets_both_segments_and_radius_a_overrides_it():
    """radius 30 mm: both segments 0.03 m; radius_a beside it wins for the a segment."""
    shapes = _collisions(_table(radius=30.0, radius_a=50.0))
    assert shapes["a1_collision"][1]["radius"] == "0.05"
    assert shapes["d1_collision"][1]["radius"] == "0.03"


def test_no_radius_keeps_the_plain_sticks():
    """A row without radii: 1 cm cylinders without end spheres, and the note names the row."""
    table = _table()
    shapes = _collisions(table)
    assert sorted(shapes) == ["a1_collision", "d1_collision"]
    assert {s[1]["radius"] for s in shapes.values()} == {"0.01"}
    note = default_radius_note(table)
    assert note.startswith("note: robot's links are default 1 cm sticks") and "rows 1 " in note
    assert default_radius_note(_table(radius=5.0)) is None


def test_housing_sits_where_a_plain_dh_product_puts_it():
    """A housing from (0, 0, -50) to (0, 0, 50) mm in frame 1: at q its centre is
    T_01(q) @ 0 and its axis z1, T_01 = Rz(q) Tz(d) Tx(a) Rx(alpha) computed here by hand."""
    housing = {"from": [0.0, 0.0, -50.0], "to": [0.0, 0.0, 50.0], "radius": 35.0}
    table = _table(housing=[housing])
    robot = robot_from_table(table)
    from kin.collision import load_collision_model

    model = load_collision_model(robot)
    index = next(
        k for k, g in enumerate(model.geometry_model.geometryObjects) if "housing" in g.name
    )
    geometry = model.geometry_model.geometryObjects[index].geometry
    assert (geometry.radius, 2 * geometry.halfLength) == pytest.approx((0.035, 0.1))
    data, geometry_data = robot.model.createData(), pin.GeometryData(model.geometry_model)
    for q in (0.0, 0.7, -1.2):
        pin.updateGeometryPlacements(
            robot.model, data, model.geometry_model, geometry_data, np.array([q])
        )
        placed = geometry_data.oMg[index]
        c, s = np.cos(q), np.sin(q)
        centre = np.array([0.3 * c, 0.3 * s, 0.1])
        z1 = np.array([s, -c, 0.0])  # Rz(q) Rx(90 deg) e_z
        assert np.allclose(placed.translation, centre, atol=1e-12), q
        assert abs(abs(placed.rotation[:, 2] @ z1) - 1.0) < 1e-12, q


@pytest.mark.parametrize(
    ("fields", "where"),
    [
        ({"radius_a": 0.0}, "radius_a"),
        ({"radius_d": -1.0}, "radius_d"),
        ({"radius_a": 2e9}, "radius_a"),
        ({"housing": [{"from": [0, 0, 0], "radius": 1.0}]}, "housing[0]"),
        ({"housing": [{"from": [0, 0, 0], "to": [0, 0, 0], "radius": 1.0}]}, "housing[0]"),
        ({"housing": [{"from": [0, 0], "to": [0, 0, 1], "radius": 1.0}]}, "housing[0].from"),
        ({"housing": [{"from": [0, 0, 0], "to": [0, 0, 1], "radius": 0}]}, "housing[0].radius"),
        ({"housing": {"from": [0, 0, 0]}}, "housing"),
    ],
)
def test_bad_volume_fields_name_the_row_and_field(fields, where):
    """A bad radius or housing: a TableError naming row 1 and the field."""
    with pytest.raises(TableError) as info:
        _table(**fields)
    assert info.value.row == 1 and info.value.field == where, str(info.value)


def test_kin_check_says_when_the_links_are_default_sticks(capsys):
    """puma560 (no radius in its table): one note line; ur5 (housings): none."""
    call(check.main, ["--robot", "puma560", "--q", "0", "0", "0", "0", "0", "0"])
    notes = [line for line in capsys.readouterr().out.splitlines() if line.startswith("note:")]
    assert len(notes) == 1 and "puma560's links are default 1 cm sticks" in notes[0]
    call(check.main, ["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "0"])
    assert "note:" not in capsys.readouterr().out


@pytest.mark.parametrize("name", ["panda", "ur10", "ur3", "ur5"])
def test_shipped_tables_state_their_body(name):
    """The tables of arms whose makers publish meshes give every row a housing."""
    table = load_robot(name).table
    assert default_radius_note(table) is None and all(row.housings for row in table.rows)


@pytest.mark.parametrize("name", ["panda", "ur10", "ur3", "ur5"])
def test_no_configuration_where_the_makers_arm_touches_the_cell_and_the_table_is_free(name):
    """Over QUICK random configurations in examples/cell.toml: 0 misses against the maker's
    collision meshes (coal on example-robot-data's URDF); the cell is hit often enough to tell."""
    counts = load_script("check_dh_volumes").compare(name, QUICK)
    assert counts.misses == 0, f"{name=} {counts}"
    assert counts.maker_hits > QUICK // 10, f"{name=} {counts}"
    assert counts.false_alarms < QUICK // 10, f"{name=} {counts}"


def test_the_comparison_sees_a_miss_with_the_sticks():
    """The same comparison with UR5's sticks (housings dropped) finds misses: the test can fail."""
    from support.stick_arms import stick_robot

    script = load_script("check_dh_volumes")
    arm = script.MakerArm("ur5")
    sticks = stick_robot("ur5")
    rng = np.random.default_rng(0)
    qs = rng.uniform(sticks.lower, sticks.upper, size=(QUICK, sticks.nq))
    from kin.collision.scene import load_scene

    maker = script._maker_verdicts(arm, load_scene(script.DEFAULT_SCENE).objects, qs)
    table = script._table_verdicts(sticks, script.DEFAULT_SCENE, qs)
    assert (maker & ~table).sum() > 0


#: The makers' named postures [rad]: Panda's SRDF 'ready', UR home, the README's UR posture.
NAMED_POSTURES = [
    ("panda", (0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785)),
    *(
        (ur, q)
        for ur in ("ur10", "ur3", "ur5")
        for q in ((0, -1.57, 0, -1.57, 0, 0), (0, -1.5, 1.5, 0, 0, 0))
    ),
]
#: Largest self-collision false-alarm fraction over QUICK configurations (seed 0), against the
#: maker's arm with its SRDF: measured 5.0 % (Panda), 1.6 % (UR10), 10.0 % (UR3), 4.0 % (UR5).
SELF_FALSE_ALARMS = {"panda": 0.07, "ur10": 0.03, "ur3": 0.12, "ur5": 0.06}


@pytest.mark.parametrize(("name", "q"), NAMED_POSTURES)
def test_named_postures_are_free_of_self_collision(name, q):
    """The makers' named postures: no self-collision of the table's own model (no SRDF), as the
    maker's arm (coal, its SRDF) says too."""
    from kin.collision import CollisionChecker, load_collision_model

    checker = CollisionChecker(load_collision_model(load_robot(name)))
    assert not checker.in_collision_batch(np.array([q], dtype=float), threads=1)[0], f"{name=}"
    script = load_script("check_dh_volumes")
    arm = script.MakerArm(name)
    geometry, _ = script._maker_self(arm, name)
    data = geometry.createData()
    maker_q = arm.q(np.array(q, dtype=float))
    assert not pin.computeCollisions(arm.model, arm.data, geometry, data, maker_q, True), name


@pytest.mark.parametrize("name", ["panda", "ur10", "ur3", "ur5"])
def test_self_collisions_agree_with_the_makers_arm(name):
    """Over QUICK random configurations: every self-collision of the maker's arm (coal on
    example-robot-data's hulls, its SRDF's pairs aside) is one of the table's (no misses), and
    the table's false alarms stay below the measured bound."""
    counts = load_script("check_dh_volumes").self_compare(name, QUICK)
    assert counts.misses == 0, f"{name=} {counts}"
    assert counts.maker_hits > 0, f"{name=} {counts}"
    assert counts.false_alarms <= SELF_FALSE_ALARMS[name] * QUICK, f"{name=} {counts}"


def test_allow_contact_skips_the_two_rows_bodies():
    """A row's [[joints.allow_contact]] drops every link pair of the two rows, reason 'table: ..',
    and survives table_text; the Panda's ready posture collides without the table's pairs."""
    from dataclasses import replace

    from dh2urdf.table_writer import table_text
    from kin.collision import CollisionChecker, load_collision_model

    panda = load_robot("panda")
    model = load_collision_model(panda)
    assert model.disabled[("frame5", "frame7")].startswith("table: the maker's SRDF disables")
    assert ("frame5", "frame7") not in model.pairs
    text = table_text(panda.table)
    assert text.count("[[joints.allow_contact]]") == 3 and "row = 5" in text
    # the same table without the allowed pairs: the 'ready' posture collides (frame3/frame5)
    rows = tuple(replace(row, allowed_contacts=()) for row in panda.table.rows)
    bare = robot_from_table(replace(panda.table, rows=rows))
    ready = np.array([NAMED_POSTURES[0][1]])
    assert CollisionChecker(load_collision_model(bare)).in_collision_batch(ready, threads=1)[0]


@pytest.mark.parametrize(
    ("entry", "where"),
    [
        ({"row": 1}, "allow_contact[0]"),
        ({"row": 2, "reason": "x"}, "allow_contact[0].row"),
        ({"row": 0, "reason": "x"}, "allow_contact[0].row"),
        ({"row": 1, "reason": " "}, "allow_contact[0].reason"),
    ],
)
def test_bad_allow_contact_names_the_field(entry, where):
    """allow_contact needs an earlier row and a one-line reason: else a TableError naming it."""
    units = {"convention": "standard", "length_unit": "mm", "angle_unit": "deg"}
    with pytest.raises(TableError) as info:
        parse_table({**units, "joints": [ROW, {**ROW, "name": "j2", "allow_contact": [entry]}]})
    assert info.value.row == 2 and info.value.field == where, str(info.value)

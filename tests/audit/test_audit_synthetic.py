"""The audit recovers a known corruption of a correct table, one kind at a time and by pairs.

A correct 7-joint table (standard DH, cm, deg, offsets, a tool offset) gives 20 samples through
the batched FK (rounded to 3 decimals of a cm); then the table file or the samples are corrupted
the way papers are (the other convention, DH angles printed for joint values, a twist sign, all
twist signs, a length sign, lengths in mm, twists and offsets in rad, samples in mm, joint
values in rad, digits truncated),
and the audit's best reading must undo exactly that corruption.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from support.synthetic_tables import ROWS, TOOL, table_toml

from dh2urdf import load_table
from kin import batch_forward_kinematics
from kin.audit import audit_samples
from kin.audit.printed import rpy_of

SAMPLES = 20
DECIMALS = 3

#: Corruption -> the change (kind, row, value) the audit must find.
EXPECTED = {
    "convention": ("convention", None, None),
    "offsets": ("offsets", None, None),
    "twist3": ("twist", 3, None),
    "twist6": ("twist", 6, None),
    "twist_all": ("twist_all", None, None),
    "d_sign4": ("d_sign", 4, None),
    "table_in_mm": ("length_unit", None, "mm"),
    "table_angles_in_rad": ("table_angle_unit", None, "rad"),
    "samples_in_mm": ("sample_length_unit", None, "mm"),
    "angles_in_rad": ("angle_unit", None, "rad"),
    "truncated": ("truncated", None, None),
    "offset2_printed": ("theta_shift", 2, "0"),
    "zero3_quarter_turn": ("theta_shift", 3, "180"),
    "joint5_reversed": ("joint_sign", 5, None),
}


def printed(value: float, truncate: bool, places: int = DECIMALS) -> str:
    """``value`` with ``places`` decimals, rounded or truncated toward zero."""
    if truncate:
        value = math.trunc(value * 10**places) / 10**places
    return f"{value:.{places}f}"


def write_case(tmp_path, corruptions, rows=ROWS, tool=TOOL, orientation=False):
    """Write the corrupted table and samples; return their paths."""
    offsets = np.array([r[3] for r in rows])
    rows = [list(r) for r in rows]
    reference = tmp_path / "correct.toml"
    reference.write_text(table_toml(rows, tool=tool), encoding="utf-8")
    correct = load_table(reference)
    q_deg = np.random.default_rng(7).uniform(-150, 150, size=(SAMPLES, len(rows)))
    poses = batch_forward_kinematics(correct, np.radians(q_deg))
    for c in corruptions:
        if c.startswith("twist") and c != "twist_all":
            rows[int(c[5:]) - 1][1] *= -1
        elif c == "twist_all":
            for r in rows:
                r[1] *= -1
        elif c == "d_sign4":
            rows[3][2] *= -1
    if "table_angles_in_rad" in corruptions:  # the numbers in rad, the file still says deg
        for r in rows:
            r[1], r[3] = math.radians(r[1]), math.radians(r[3])
    convention = "modified" if "convention" in corruptions else "standard"
    scale = 10.0 if "table_in_mm" in corruptions else 1.0
    table = tmp_path / "table.toml"
    table.write_text(table_toml(rows, convention, scale, tool), encoding="utf-8")
    joint = q_deg + (offsets if "offsets" in corruptions else 0.0)
    if "offset2_printed" in corruptions:  # joint 2 printed as its DH angle
        joint[:, 1] = q_deg[:, 1] + offsets[1]
    if "zero3_quarter_turn" in corruptions:  # joint 3 counted from a zero a quarter turn away
        joint[:, 2] -= 90.0
    if "joint5_reversed" in corruptions:  # joint 5 counted the other way
        joint[:, 4] *= -1.0
    if "angles_in_rad" in corruptions:
        joint = np.radians(joint)
    length = 10.0 if "samples_in_mm" in corruptions else 1.0  # cm -> mm
    truncate = "truncated" in corruptions
    header = [f"q{i}" for i in range(1, len(rows) + 1)] + ["x", "y", "z"]
    if orientation:
        header += ["roll", "pitch", "yaw"]
    lines = [",".join(header)]
    for k in range(SAMPLES):
        values = [printed(v, truncate) for v in poses[k, :3, 3] * 100.0 * length]
        if orientation:
            values += [printed(v, truncate, 4) for v in np.degrees(rpy_of(poses[k, :3, :3]))]
        lines.append(",".join([*(repr(float(v)) for v in joint[k]), *values]))
    samples = tmp_path / "samples.csv"
    samples.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return table, samples


UNITS = {"length_unit", "table_angle_unit", "sample_length_unit", "angle_unit"}


def key(change) -> tuple:
    """(kind, row, value): the unit's name, a new offset [deg], else None."""
    value = change.value if change.kind in UNITS else None
    if change.kind == "theta_shift":
        value = f"{math.degrees(float(change.value)):.6g}"
    return (change.kind, change.row, value)


def found(audit) -> set[tuple]:
    """The best reading's changes as (kind, row, value)."""
    return {key(c) for c in audit.best.reading.changes}


#: Lengths of the table and of the samples both in mm: one consistent arm, nothing to find.
UNIFORM = ("table_in_mm", "samples_in_mm")
#: Pairs that say nothing more than one of them (joint 2's offset with all offsets), that other
#: changes say as well (all offsets printed and joint 3 a quarter turn back: the offsets of
#: rows 2 and 5 dropped), or that no pair of changes undoes (a quarter turn added to an offset
#: written in the wrong unit).
OVERLAPPING = {
    ("offsets", "offset2_printed"),
    ("offsets", "zero3_quarter_turn"),
    ("table_angles_in_rad", "zero3_quarter_turn"),
}
CASES = [(c,) for c in EXPECTED] + [
    pair
    for pair in itertools.combinations(EXPECTED, 2)
    if pair != UNIFORM and pair not in OVERLAPPING
]


#: Every single corruption and every sixth pair in the default run; the other pairs are slow.
FAST_CASES = [
    pytest.param(c, id="+".join(c), marks=() if len(c) == 1 or k % 6 == 0 else pytest.mark.slow)
    for k, c in enumerate(CASES)
]


@pytest.mark.parametrize("corruptions", FAST_CASES)
def test_audit_recovers_the_corruption(tmp_path, corruptions):
    """The best reading is exactly the corruption, and it reproduces every sample."""
    table, samples = write_case(tmp_path, corruptions)
    audit = audit_samples(table, samples)
    expected = {EXPECTED[c] for c in corruptions}
    assert found(audit) == expected, f"{corruptions=} best: {audit.best.reading.label}"
    assert audit.best.count == SAMPLES, f"{corruptions=} {audit.best.count=}"


def test_correct_table_is_the_best_reading(tmp_path):
    """Samples of the table itself: the table as written ranks first, every sample reproduced."""
    table, samples = write_case(tmp_path, ())
    audit = audit_samples(table, samples)
    assert audit.best.reading.changes == (), audit.best.reading.label
    assert audit.best.count == SAMPLES
    assert audit.best.max_residual_m < math.sqrt(3) * 0.5e-5  # half of 0.001 cm per axis


def test_uniform_unit_error_is_no_error(tmp_path):
    """Table and samples both written in mm under a cm label: the table as written reproduces."""
    table, samples = write_case(tmp_path, UNIFORM)
    audit = audit_samples(table, samples)
    assert audit.best.reading.changes == (), audit.best.reading.label
    assert audit.best.count == SAMPLES


def test_last_twist_needs_the_orientation(tmp_path):
    """Without a tool offset the last twist moves no point: only printed rpy reveal its sign."""
    rows = [*ROWS[:6], (0.0, 90.0, 8.0, 0.0)]
    table, samples = write_case(tmp_path, ("twist7",), rows=rows, tool="")
    blind = audit_samples(table, samples)
    assert blind.best.reading.changes == (), blind.best.reading.label
    table, samples = write_case(tmp_path, ("twist7",), rows=rows, tool="", orientation=True)
    audit = audit_samples(table, samples)
    assert found(audit) == {("twist", 7, None)}, audit.best.reading.label
    assert audit.as_written().count == 0


def test_seven_joints_twenty_samples_scores_every_reading(tmp_path):
    """A 7-joint table with 20 samples: pairs and refits included, over 300 readings scored (the
    time it takes is scripts' business, not a test's)."""
    table, samples = write_case(tmp_path, ("convention", "twist3"))
    audit = audit_samples(table, samples)
    assert len(audit.scores) > 300, len(audit.scores)


@pytest.mark.parametrize(
    ("corruption", "expected"),
    [
        ("convention", {("convention", None, None)}),
        ("slide_length", {("offsets", None, None)}),
        ("samples_in_cm", {("sample_length_unit", None, "cm")}),
    ],
)
def test_prismatic_joint(tmp_path, corruption, expected):
    """A SCARA-like arm (mm, a prismatic joint): its values are lengths, its offset is d."""
    from support.cli_helper import write_rrpr4

    path = write_rrpr4(tmp_path)
    correct = load_table(path)
    rng = np.random.default_rng(3)
    q = np.column_stack(
        [
            rng.uniform(-150, 150, (SAMPLES, 2)),
            rng.uniform(0, 200, SAMPLES),
            rng.uniform(-180, 180, SAMPLES),
        ]
    )
    q_si = np.column_stack([np.radians(q[:, :2]), q[:, 2] / 1000.0, np.radians(q[:, 3])])
    positions = batch_forward_kinematics(correct, q_si)[:, :3, 3] * 1000.0  # mm
    if corruption == "convention":
        text = path.read_text(encoding="utf-8").replace('"standard"', '"modified"')
        path.write_text(text, encoding="utf-8")
    if corruption == "slide_length":
        q[:, 2] += 20.0  # the printed value is the DH length q + d
    scale = 0.1 if corruption == "samples_in_cm" else 1.0
    if corruption == "samples_in_cm":
        q[:, 2] *= scale
    lines = ["q1,q2,q3,q4,x,y,z"]
    for k in range(SAMPLES):
        xyz = [printed(v * scale, False, 4) for v in positions[k]]
        lines.append(",".join([*(repr(float(v)) for v in q[k]), *xyz]))
    samples = tmp_path / "samples.csv"
    samples.write_text("\n".join(lines) + "\n", encoding="utf-8")
    audit = audit_samples(path, samples)
    assert found(audit) == expected, audit.best.reading.label
    assert audit.best.count == SAMPLES


def random_rows(seed: int) -> tuple[tuple[float, float, float, float], ...]:
    """A random 7-joint table (cm, deg) with the rows the corruptions need (twists 3 and 6,
    d4, an offset in row 2)."""
    rng = np.random.default_rng(seed)
    rows = []
    for _ in range(7):
        a = round(float(rng.choice([0.0, rng.uniform(2.0, 30.0)])), 2)
        d = round(float(rng.choice([0.0, rng.uniform(2.0, 30.0)])), 2)
        alpha = float(rng.choice([-90.0, 90.0, 0.0, 45.0]))
        theta = float(rng.choice([0.0, 0.0, 90.0, -90.0, 30.0]))
        rows.append([a, alpha, d, theta])
    rows[2][1], rows[5][1], rows[3][2], rows[1][3] = 90.0, -90.0, 12.5, 90.0
    return tuple(tuple(r) for r in rows)


RANDOM_CASES = [
    (seed, corruption)
    for seed in (100, 101, 102)
    for k, corruption in enumerate(CASES)
    if len(corruption) == 1 or k % 3 == seed % 3
]


@pytest.mark.parametrize(
    ("seed", "corruptions"),
    [  # the first table's single corruptions in the default run, the rest slow
        pytest.param(*case, marks=() if case[0] == 100 and len(case[1]) == 1 else pytest.mark.slow)
        for case in RANDOM_CASES
    ],
)
def test_random_tables_give_back_the_correct_table(tmp_path, seed, corruptions):
    """Random tables: the best reading's table and sample units are those of the correct table
    (however its changes are described: all twists but one may be the other ones flipped)."""
    from kin.audit import apply_changes, elementary_changes, load_audited_table

    rows = random_rows(seed)
    table, samples = write_case(tmp_path, corruptions, rows=rows)
    audit = audit_samples(table, samples)
    audited = load_audited_table(table)
    shifted = ("theta_shift", 3, f"{rows[2][3] + 90.0:.6g}")  # this table's offset + 90 deg
    wanted = {shifted if c == "zero3_quarter_turn" else EXPECTED[c] for c in corruptions}
    changes = tuple(c for c in elementary_changes(audited) if key(c) in wanted)
    expected = apply_changes(audited, changes)
    best = audit.best.reading
    assert audit.best.count == SAMPLES, f"{seed=} {corruptions=} {best.label}"
    assert best.table.convention == expected.table.convention
    params = [[(r.a, r.alpha, r.d, r.theta) for r in t.rows] for t in (best.table, expected.table)]
    assert np.allclose(params[0], params[1], atol=1e-12), f"{seed=} {corruptions=} {best.label}"
    assert (best.sample_angle_unit, best.sample_length_unit, best.truncated) == (
        expected.sample_angle_unit,
        expected.sample_length_unit,
        expected.truncated,
    ), f"{seed=} {corruptions=} {best.label}"


def test_coinciding_axes_leave_the_offset_undecided(tmp_path):
    """Joints 1 and 2 about one axis (alpha1 = 0, a1 = 0): an offset printed into joint 2 may as
    well belong to joint 1; the report names the other reading as equally good."""
    from kin.audit.report import equally_good, sample_audit_text

    rows = ((0.0, 0.0, 30.0, 0.0), (25.0, 90.0, 4.0, 90.0), *ROWS[2:])
    table, samples = write_case(tmp_path, ("offset2_printed",), rows=rows)
    audit = audit_samples(table, samples)
    labels = {audit.best.reading.label, *(s.reading.label for s in equally_good(audit))}
    assert {"theta2: 90 -> 0 deg", "theta1: 0 -> -90 deg"} <= labels, labels
    assert "equally good (the samples cannot tell them apart)" in sample_audit_text(audit)

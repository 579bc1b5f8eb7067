"""The URDF text written without yourdfpy is the text yourdfpy's writer and lxml give.

``urdf_string`` writes the elements of a table with string formatting (no yourdfpy, trimesh or
lxml: a model from a table file starts as fast as a shipped one). The reference here is the
writer it replaced: the same elements as a yourdfpy model (``build_urdf``), serialised by
yourdfpy's ``write_xml`` and lxml's pretty printer, with the MuJoCo extension and the placeholder
note inserted by lxml. Compared byte for byte on every shipped table and on generated tables
(gimbal-locked origins, prismatic joints, masses, names XML must escape).
"""

from __future__ import annotations

import math
import subprocess
import sys

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree
from support.urdf_text import body, yourdfpy_text

from dh2urdf import ROBOTS, get_robot, parse_table
from dh2urdf.urdf_elements import origin_rpy
from dh2urdf.urdf_writer import urdf_string


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_shipped_table_text_equals_yourdfpy(name):
    """Every shipped table: the same bytes as yourdfpy's writer."""
    table = get_robot(name).load_table()
    assert body(urdf_string(table)) == yourdfpy_text(table), f"{name=}"


ANGLES = st.one_of(
    st.sampled_from([0.0, 90.0, -90.0, 180.0, -180.0, 45.0, 1e-14, 89.99999999]),
    st.floats(min_value=-360.0, max_value=360.0, allow_nan=False),
)
LENGTHS = st.one_of(
    st.sampled_from([0.0, -0.0, 1e-12, 0.5, 1e3, 1e6 * 0.999]),
    st.floats(min_value=-2e3, max_value=2e3, allow_nan=False),
)
NAMES = st.text(
    alphabet=st.sampled_from(list("ab_&<>\"'\t é") + ["\n", "Ω"]), min_size=1, max_size=6
).filter(str.strip)


@st.composite
def tables(draw: st.DrawFn) -> dict:
    """A table document: 1 to 7 rows of any angles and lengths [mm, deg], maybe masses."""
    rows = []
    names = draw(st.lists(NAMES, min_size=1, max_size=7, unique=True))
    with_mass = draw(st.booleans())
    for name in names:
        prismatic = draw(st.booleans()) and draw(st.booleans())
        lower = draw(st.floats(min_value=-500.0, max_value=0.0))
        row = {
            "name": name,
            "type": "prismatic" if prismatic else "revolute",
            "a": draw(LENGTHS),
            "alpha": draw(ANGLES),
            "d": draw(LENGTHS),
            "theta": draw(ANGLES),
            "limits": [lower, lower + draw(st.floats(min_value=0.0, max_value=500.0))],
        }
        if with_mass or draw(st.booleans()) and draw(st.booleans()):
            row["mass"] = draw(st.floats(min_value=0.01, max_value=50.0))
            row["radius"] = draw(st.floats(min_value=1.0, max_value=80.0))
        rows.append(row)
    document = {
        "name": draw(NAMES),
        "source": draw(NAMES),
        "convention": draw(st.sampled_from(["standard", "modified"])),
        "length_unit": "mm",
        "angle_unit": "deg",
        "joints": rows,
    }
    for key in ("base", "tool"):
        if draw(st.booleans()):
            document[key] = {
                "xyz": draw(st.lists(LENGTHS, min_size=3, max_size=3)),
                "rpy": draw(st.lists(ANGLES, min_size=3, max_size=3)),
            }
    return document


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(document=tables())
def test_generated_table_text_equals_yourdfpy(document):
    """Generated tables (any angle, gimbal lock, escaping, masses): the same bytes as yourdfpy."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # unit warnings of long arms are not the point here
        table = parse_table(document, "generated.toml")
    text = urdf_string(table)
    assert body(text) == yourdfpy_text(table)
    assert etree.fromstring(text.encode("utf-8")).get("name") == table.name


@pytest.mark.parametrize(
    "rpy", [(0.3, math.pi / 2, -0.2), (0.3, -math.pi / 2, 1.1), (-2.0, 0.4, 3.0), (0, 0, math.pi)]
)
def test_origin_rpy_rebuilds_the_rotation(rpy):
    """origin_rpy inverts Rz(yaw) Ry(pitch) Rx(roll), at gimbal lock too (Pinocchio rebuilds it)."""
    import numpy as np
    import pinocchio as pin

    R = pin.rpy.rpyToMatrix(*rpy)
    T = np.eye(4)
    T[:3, :3] = R
    again = pin.rpy.rpyToMatrix(*(float(v) for v in origin_rpy(T)))
    np.testing.assert_allclose(again, R, atol=1e-12)


def test_writing_a_table_imports_no_yourdfpy_trimesh_or_lxml():
    """urdf_string on a table file loads none of yourdfpy, trimesh, lxml."""
    path = get_robot("ur5").table_path
    code = (
        "import sys; from dh2urdf import load_table, urdf_string; "
        f"urdf_string(load_table({str(path)!r})); "
        "print(sorted(m for m in ('yourdfpy', 'trimesh', 'lxml') if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"

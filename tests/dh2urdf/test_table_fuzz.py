"""Fuzz the table loader with hypothesis: mutated valid tables either load with a finite model or
raise an error of the package's family (``dh2urdf.Dh2UrdfError``), nothing else.

Each example takes a shipped table and mutates one to three of its fields (numbers, strings,
lists, missing keys, huge or non-finite values, wrong types). An accepted table must give finite
forward kinematics, computed here by an independent NumPy DH product (``tests/support/dh_reference``), at
q = 0 and at both limits, and a URDF without a non-finite number.
"""

from __future__ import annotations

import copy
import math
import sys
from xml.etree import ElementTree

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support.dh_reference import dh_matrices

from dh2urdf import ROBOTS, Dh2UrdfError, get_robot, parse_table
from dh2urdf.urdf_writer import urdf_string

#: The shipped tables as parsed TOML documents.
DOCUMENTS = {
    name: tomllib.loads(get_robot(name).table_path.read_text(encoding="utf-8")) for name in ROBOTS
}

#: Values a mutated field may take: the plausible, the huge, the non-finite and the wrong type.
VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e3, max_value=1e3),
    st.sampled_from([1e308, -1e308, 1e200, 5e-324, 0.0, -0.0]),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.text(max_size=5),
    st.booleans(),
    st.lists(st.floats(allow_nan=True), max_size=4),
    st.none(),
)

JOINT_KEYS = ("a", "alpha", "d", "theta", "limits", "type", "name", "velocity", "effort")
TOP_KEYS = ("convention", "length_unit", "angle_unit", "name", "joints", "base", "tool")


@st.composite
def mutated_tables(draw: st.DrawFn) -> dict:
    """A shipped table with one to three fields replaced, added or removed."""
    document = copy.deepcopy(DOCUMENTS[draw(st.sampled_from(sorted(DOCUMENTS)))])
    for _ in range(draw(st.integers(1, 3))):
        value = None if draw(st.booleans()) and draw(st.booleans()) else draw(VALUES)
        where = draw(st.sampled_from(["joint", "joint", "joint", "limit", "top"]))
        container = document
        if where == "top":
            key = draw(st.sampled_from(TOP_KEYS))
        else:
            rows = document.get("joints")
            if not isinstance(rows, list) or not rows or not isinstance(rows[0], dict):
                continue
            row = rows[draw(st.integers(0, len(rows) - 1))]
            if where == "limit":
                limits = row.get("limits", [0.0, 0.0])
                limits = list(limits) if isinstance(limits, list) else [limits, limits]
                limits += [0.0] * (2 - len(limits))  # an earlier mutation may have shortened it
                limits[draw(st.integers(0, 1))] = value
                row["limits"] = limits
                continue
            container, key = row, draw(st.sampled_from(JOINT_KEYS))
        if value is None:
            container.pop(key, None)
        else:
            container[key] = value
    return document


def _finite_fk(table) -> bool:  # noqa: ANN001
    """Whether the NumPy DH product is finite at q = 0 and at both limits."""
    prismatic = np.array([row.joint_type == "prismatic" for row in table.rows])
    a = np.array([row.a for row in table.rows])
    alpha = np.array([row.alpha for row in table.rows])
    d = np.array([row.d for row in table.rows])
    theta = np.array([row.theta for row in table.rows])
    for q in (np.zeros(table.dof), table.lower, table.upper):
        links = dh_matrices(
            table.convention,
            a,
            alpha,
            np.where(prismatic, q + d, d),
            np.where(prismatic, theta, q + theta),
        )
        T = table.T_world_base
        for link in links:
            T = T @ link
        T = T @ table.T_last_tool
        if not np.isfinite(T).all():
            return False
    return True


#: URDF attributes that hold numbers (names and flags are text: a table named "INF" is fine).
NUMBER_ATTRIBUTES = {
    *("xyz", "rpy", "lower", "upper", "effort", "velocity", "damping", "friction", "value"),
    *("radius", "length", "size", "scale", "rgba", "ixx", "ixy", "ixz", "iyy", "iyz", "izz"),
}


def _non_finite_numbers(urdf: str) -> list[str]:
    """``element@attribute=value`` of every numeric attribute of ``urdf`` not all finite numbers."""
    bad = []
    for element in ElementTree.fromstring(urdf.encode()).iter():
        for key, value in element.attrib.items():
            if key not in NUMBER_ATTRIBUTES:
                continue
            try:
                finite = all(math.isfinite(float(word)) for word in value.split())
            except ValueError:
                finite = False
            if not finite:
                bad.append(f"{element.tag}@{key}={value!r}")
    return bad


def test_the_number_check_reads_numbers_not_names():
    """The check itself: a name "inf" passes, an ``inf`` or a ``nan`` in a number does not."""
    robot = '<robot name="inf"><link name="nan"/><joint name="j" type="fixed">{}</joint></robot>'
    assert not _non_finite_numbers(robot.format('<origin xyz="0 1e-3 2" rpy="0 0 0"/>'))
    assert _non_finite_numbers(robot.format('<origin xyz="0 inf 2" rpy="0 0 0"/>'))
    assert _non_finite_numbers(robot.format('<origin xyz="0 0 0" rpy="nan 0 0"/>'))
    assert _non_finite_numbers(robot.format('<limit lower="-Infinity" upper="1"/>'))


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(document=mutated_tables())
def test_mutated_tables_load_finite_or_raise_the_family(document):
    try:
        table = parse_table(document, "fuzz.toml")
    except Dh2UrdfError as err:
        assert str(err).startswith("fuzz.toml"), str(err)  # names the file
        return
    assert _finite_fk(table), "an accepted table gives non-finite forward kinematics"
    bad = _non_finite_numbers(urdf_string(table))  # every number the URDF carries is finite
    assert not bad, f"non-finite value in the URDF: {bad}"
    assert all(row.lower <= row.upper for row in table.rows)
    assert all(math.isfinite(v) for row in table.rows for v in (row.lower, row.upper))


@pytest.mark.parametrize("name", sorted(DOCUMENTS))
def test_unmutated_tables_load(name):
    """The generator's starting points are valid (else every example would raise)."""
    assert _finite_fk(parse_table(copy.deepcopy(DOCUMENTS[name]), f"{name}.toml"))

"""URDF -> DH table: every serial arm of example-robot-data, and synthetic URDFs with the cases DH
leaves free, against Pinocchio's FK of the original URDF (1000 random q, 1e-12)."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from support.urdf_reference import ARMS, UrdfReference, erd

from dh2urdf import Dh2UrdfError, parse_table
from dh2urdf.dh_table import DHTable, dh_link_transform
from dh2urdf.table_writer import table_text
from dh2urdf.urdf_chain import UrdfChainError, read_chain
from dh2urdf.urdf_to_dh import table_from_urdf

if __import__("sys").version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib

SAMPLES = 1000
TOLERANCE = 1e-12


def dh_product(table: DHTable, q: np.ndarray) -> np.ndarray:
    """``T_base_tip`` of the table at ``q``: a plain product of its rows (no package code)."""
    product = np.array(table.T_world_base)
    for row, value in zip(table.rows, q, strict=True):
        theta = row.theta + (value if row.joint_type == "revolute" else 0.0)
        d = row.d + (value if row.joint_type == "prismatic" else 0.0)
        product = product @ dh_link_transform(table.convention, row.a, row.alpha, d, theta)
    return product @ table.T_last_tool


def _samples(table: DHTable, count: int, seed: int) -> np.ndarray:
    lower = np.maximum(table.lower, -2 * math.pi)
    upper = np.minimum(table.upper, 2 * math.pi)
    return np.random.default_rng(seed).uniform(lower, upper, size=(count, table.dof))


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("arm", list(ARMS))
def test_extracted_table_equals_the_urdf_fk(arm, convention):
    """1000 random q: the extracted table's DH product equals Pinocchio's FK of the URDF."""
    relative, base, tip = ARMS[arm]
    path = erd(relative)
    chain = read_chain(path, base, tip)
    table = table_from_urdf(path, base, tip, convention)
    assert table.joint_names == tuple(joint.name for joint in chain.joints)
    reference = UrdfReference(path, chain.base, chain.tip, table.joint_names)
    worst = 0.0
    for q in _samples(table, SAMPLES, seed=len(arm)):
        worst = max(worst, float(np.abs(dh_product(table, q) - reference.pose(q)).max()))
    assert worst < TOLERANCE, f"{arm=} {convention=} {worst=}"


@pytest.mark.parametrize("arm", ["ur5", "panda", "kinova", "tiago", "double_pendulum"])
def test_table_file_round_trip_keeps_the_fk(arm):
    """The table written as TOML and read back gives the same FK (1e-12) and the same rows."""
    relative, base, tip = ARMS[arm]
    table = table_from_urdf(erd(relative), base, tip)
    again = parse_table(tomllib.loads(table_text(table)), "<round trip>")
    for row, other in zip(table.rows, again.rows, strict=True):
        assert (row.a, row.alpha, row.d, row.theta) == (other.a, other.alpha, other.d, other.theta)
        assert (row.lower, row.upper, row.joint_type) == (
            other.lower,
            other.upper,
            other.joint_type,
        )
    for q in _samples(table, 200, seed=3):
        assert np.abs(dh_product(table, q) - dh_product(again, q)).max() < TOLERANCE


def test_ur5_reads_as_the_makers_dh_up_to_signs():
    """UR5: the extracted lengths are the maker's DH parameters (d1, a2, a3, d4, d5, d6)."""
    table = table_from_urdf(erd(ARMS["ur5"][0]), tip="tool0")
    a = [abs(row.a) for row in table.rows]
    d = [abs(row.d) for row in table.rows]
    np.testing.assert_allclose(a, [0, 0.425, 0.39225, 0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(d, [0.089159, 0, 0, 0.10915, 0.09465, 0.0823], atol=1e-12)


# --- synthetic URDFs: the free choices of DH and the bad inputs ------------------------------

_LINK = '<link name="{name}"/>'
_JOINT = """<joint name="{name}" type="{kind}">
  <parent link="{parent}"/><child link="{child}"/>
  <origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>{extra}
  <limit lower="-2" upper="2.5" velocity="1.5" effort="20"/>
</joint>"""


def _urdf(joints: list[dict], extra_links: tuple[str, ...] = (), name: str = "synthetic") -> str:
    links = ["l0"] + [f"l{i}" for i in range(1, len(joints) + 1)] + list(extra_links)
    parts = [f'<robot name="{name}">'] + [_LINK.format(name=link) for link in links]
    for i, joint in enumerate(joints, start=1):
        fields = {"name": f"j{i}", "kind": "revolute", "parent": f"l{i - 1}", "child": f"l{i}"}
        fields |= {"xyz": "0 0 0", "rpy": "0 0 0", "axis": "0 0 1", "extra": ""} | joint
        parts.append(_JOINT.format(**fields))
    return "\n".join(parts + ["</robot>"])


SYNTHETIC = {
    "negative_axes_and_rpy": [
        {"axis": "0 0 -1", "xyz": "0.1 0.2 0.3", "rpy": "0.3 -0.2 0.9"},
        {"axis": "0 -1 0", "xyz": "0 0.05 0.4", "rpy": "1.2 0 0"},
        {"axis": "-0.6 0 0.8", "xyz": "0.3 0 0.1", "rpy": "0 0.4 0"},
        {"axis": "1 0 0", "xyz": "0.2 0.1 -0.05", "rpy": "0.1 0.2 0.3"},
    ],
    "prismatic": [
        {"axis": "0 0 1"},
        {"kind": "prismatic", "axis": "0 0 -1", "xyz": "0.2 0 0.3"},
        {"kind": "prismatic", "axis": "1 0 0", "xyz": "0 0.1 0", "rpy": "0 0 0.5"},
        {"axis": "0 1 0", "xyz": "0.1 0 0"},
    ],
    "parallel_and_meeting": [
        {"axis": "0 0 1", "xyz": "0 0 0.1"},
        {"axis": "0 1 0", "xyz": "0 0.1 0.2"},
        {"axis": "0 1 0", "xyz": "0.4 0 0"},
        {"axis": "0 1 0", "xyz": "0.3 -0.05 0"},
        {"axis": "0 0 1", "xyz": "0 0 0.1"},
        {"axis": "0 0 1", "xyz": "0 0 0.1"},
    ],
    "continuous": [
        {"kind": "continuous", "axis": "0 0 1"},
        {"kind": "continuous", "axis": "1 0 0", "xyz": "0 0 0.5"},
    ],
}


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("case", list(SYNTHETIC))
def test_synthetic_chains(case, convention, tmp_path):
    """Negative and skew axes, rpy origins, prismatic, parallel, meeting, coincident and
    continuous joints: the table's FK equals the URDF's."""
    path = tmp_path / f"{case}.urdf"
    path.write_text(_urdf(SYNTHETIC[case]))
    table = table_from_urdf(path, convention=convention)
    reference = UrdfReference(path, "l0", f"l{table.dof}", table.joint_names)
    for q in _samples(table, 300, seed=11):
        assert np.abs(dh_product(table, q) - reference.pose(q)).max() < TOLERANCE, f"{case=}"
    kinds = [row.joint_type for row in table.rows]
    expected = [
        "prismatic" if j.get("kind") == "prismatic" else "revolute" for j in SYNTHETIC[case]
    ]
    assert kinds == expected


def test_nearly_parallel_axes_are_exact_with_a_far_common_normal(tmp_path):
    """Axes 3.7e-6 rad from parallel (a rounded rpy of 1.5708): exact to the rounding of a
    14 km common normal (DH has no other exact reading; no closed form will see them parallel)."""
    path = tmp_path / "near.urdf"
    path.write_text(
        _urdf([{"axis": "0 0 -1"}, {"axis": "0 -1 0", "xyz": "0 0.05 0.4", "rpy": "1.5708 0 0"}])
    )
    table = table_from_urdf(path)
    assert abs(table.rows[0].d) > 1e4  # the far foot of the common normal
    reference = UrdfReference(path, "l0", "l2", table.joint_names)
    for q in _samples(table, 300, seed=5):
        assert np.abs(dh_product(table, q) - reference.pose(q)).max() < 1e-10


def test_parallel_axes_have_no_offset_along_them(tmp_path):
    """Parallel axes 2, 3, 4: the common normals pass through the previous origin (d = 0)."""
    path = tmp_path / "parallel.urdf"
    path.write_text(_urdf(SYNTHETIC["parallel_and_meeting"]))
    table = table_from_urdf(path)
    # Standard row i joins axis i to axis i + 1: rows 2 and 3 join the parallel axes 2-3, 3-4.
    assert table.rows[1].d == 0.0 and table.rows[2].d == 0.0
    assert table.rows[1].alpha == 0.0 and table.rows[2].alpha == 0.0
    assert table.rows[4].a == 0.0 and table.rows[4].alpha == 0.0  # coincident axes 5 and 6


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("not xml at all", "not XML"),
        ("<html><body/></html>", "not a URDF"),
        (_urdf([{}], name="x").replace('type="revolute"', 'type="floating"'), "floating"),
        (_urdf([{"axis": "0 0 0"}]), "is no direction"),
        (
            _urdf([{}, {"extra": '<mimic joint="j1"/>'}]),
            "mimic",
        ),
    ],
)
def test_bad_urdfs_are_one_clear_error(text, needle, tmp_path):
    """Not XML, not a URDF, a floating, zero-axis or mimic joint: the package's error, named."""
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    with pytest.raises(Dh2UrdfError, match=needle) as caught:
        table_from_urdf(path)
    assert str(path) in str(caught.value) and "\n" not in str(caught.value)


def test_unknown_links_and_no_path_name_the_links(tmp_path):
    """An unknown base or tip lists the links; a tip that is not below the base says so."""
    path = tmp_path / "side.urdf"
    path.write_text(
        _urdf([{}, {}], extra_links=("camera",)).replace(
            "</robot>",
            '<joint name="cam" type="fixed"><parent link="l1"/><child link="camera"/></joint></robot>',
        )
    )
    with pytest.raises(UrdfChainError, match="no link 'nope' for the tip; links: l0, l1, l2"):
        table_from_urdf(path, tip="nope")
    with pytest.raises(UrdfChainError, match="no path from the base 'l2' down to the tip 'l1'"):
        table_from_urdf(path, base="l2", tip="l1")
    # The camera hangs off l1 (a side branch): the default tip is the chain's end, l2.
    assert read_chain(path).tip == "l2"
    assert table_from_urdf(path, tip="camera").dof == 1


def test_several_leaves_below_the_last_joint_name_the_candidates():
    """Panda's URDF ends in two fingers: the error lists them and says --tip."""
    with pytest.raises(
        UrdfChainError, match="panda_leftfinger, panda_rightfinger; choose one with --tip"
    ):
        read_chain(erd(ARMS["panda"][0]))


def test_xacro_without_xacrodoc_says_how(tmp_path, monkeypatch):
    """A .xacro file without the optional xacrodoc: one line with the install command."""
    import builtins

    real_import = builtins.__import__

    def no_xacrodoc(name, *args, **kwargs):
        if name == "xacrodoc":
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_xacrodoc)
    path = tmp_path / "arm.urdf.xacro"
    path.write_text(_urdf([{}]))
    with pytest.raises(UrdfChainError, match=r'pip install "dh-kinematics\[xacro\]"'):
        read_chain(path)


def test_table_quaternion_is_read_and_a_bad_one_named(tmp_path):
    """[tool] quat_wxyz: the rotation it means; a non-unit one names the field."""
    base = 'name = "q"\nconvention = "standard"\nlength_unit = "m"\nangle_unit = "rad"\n'
    row = '[[joints]]\ntype = "revolute"\na = 0.1\nalpha = 0.0\nd = 0.0\ntheta = 0.0\nlimits = [-1, 1]\n'
    half = math.sqrt(0.5)
    good = tomllib.loads(
        base + row + f"[tool]\nxyz = [0, 0, 0.2]\nquat_wxyz = [{half}, 0, {half}, 0]\n"
    )
    tool = parse_table(good).T_last_tool
    np.testing.assert_allclose(tool[:3, :3], pin.rpy.rpyToMatrix(0, math.pi / 2, 0), atol=1e-15)
    np.testing.assert_allclose(tool[:3, 3], [0, 0, 0.2])
    bad = tomllib.loads(base + row + "[tool]\nquat_wxyz = [1, 1, 0, 0]\n")
    with pytest.raises(Dh2UrdfError, match=r"field 'tool.quat_wxyz': expected a unit quaternion"):
        parse_table(bad)

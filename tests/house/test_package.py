"""Package surface: sorted, existing public names; the sorted robot registry; loadable files."""

from __future__ import annotations

import importlib
import sys

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib
from pathlib import Path

import numpy as np
import pytest
import yourdfpy
from support.dh_reference import fk_frames, load_reference, random_configurations, rotation_angle

import dh2urdf
from dh2urdf import ROBOTS, get_robot, load_table, robot_names

PACKAGES = ("dh2urdf", "kin", "kin.audit", "kin.ik", "kin.path", "kin.viewer", "reproduction")
PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


@pytest.mark.parametrize("package", PACKAGES)
def test_every_name_in_all_exists(package):
    """Each name of __all__ is an attribute of the package (no dangling re-export)."""
    module = importlib.import_module(package)
    missing = [name for name in module.__all__ if not hasattr(module, name)]
    assert module.__all__, f"{package=} has an empty __all__"
    assert not missing, f"{package=} {missing=}"


@pytest.mark.parametrize("package", PACKAGES)
def test_all_is_sorted_without_duplicates(package):
    """__all__ is sorted (case-sensitive, as ruff sorts it) and lists each name once."""
    names = list(importlib.import_module(package).__all__)
    assert names == sorted(names), f"{package=}"
    assert len(names) == len(set(names)), f"{package=}"


@pytest.mark.parametrize("package", ["dh2urdf", "kin"])
def test_version_matches_pyproject(package):
    """__version__ of the package is the project version of pyproject.toml."""
    version = tomllib.loads(PYPROJECT.read_text(encoding="utf-8"))["project"]["version"]
    assert importlib.import_module(package).__version__ == version, f"{package=}"


def test_robot_registry_is_sorted_and_consistent():
    """ROBOTS is sorted by name, robot_names() follows it, and each entry is keyed by its name."""
    assert list(ROBOTS) == sorted(ROBOTS)
    assert robot_names() == tuple(ROBOTS)
    assert len(robot_names()) == 12
    for name, description in ROBOTS.items():
        assert description.name == name, f"{name=}"
        assert description.tags, f"{name=} has no tags"
        assert get_robot(name) is description


def test_every_table_file_is_registered():
    """Each dh2urdf/tables/*.toml has a registry entry and each entry has its table file."""
    tables_dir = Path(dh2urdf.__file__).resolve().parent / "tables"
    stems = sorted(path.stem for path in tables_dir.glob("*.toml"))
    assert stems == list(robot_names())


@pytest.mark.parametrize("robot", robot_names())
def test_table_loads(robot):
    """The robot's table loads, its name is the registry name, and it has its joints."""
    table = load_table(get_robot(robot).table_path)
    assert table.name == robot, f"{robot=}"
    assert table.dof == len(load_reference(get_robot(robot).table_path).names) >= 2, f"{robot=}"
    assert table.convention in ("standard", "modified"), f"{robot=}"


@pytest.mark.parametrize("robot", robot_names())
def test_committed_urdf_loads_and_validates_in_yourdfpy(robot):
    """urdf/<robot>.urdf loads in yourdfpy, validates, and has the table's joints and the tool."""
    path = get_robot(robot).urdf_path
    model = yourdfpy.URDF.load(str(path), load_meshes=False)
    assert model.validate(), f"{robot=} {model.errors}"
    table = load_table(get_robot(robot).table_path)
    assert tuple(model.actuated_joint_names) == table.joint_names, f"{robot=}"
    expected_links = {"base_link", "tool", *(f"frame{i}" for i in range(table.dof + 1))}
    assert expected_links <= set(model.link_map), f"{robot=}"


@pytest.mark.parametrize("robot", robot_names())
def test_yourdfpy_fk_of_committed_urdf_matches_numpy(robot):
    """yourdfpy's own FK of the committed URDF puts the tool where the NumPy DH product does."""
    model = yourdfpy.URDF.load(str(get_robot(robot).urdf_path), load_meshes=False)
    ref = load_reference(get_robot(robot).table_path)
    q_all = random_configurations(ref.lower, ref.upper, 20, seed=1)
    expected = fk_frames(ref, q_all)[:, -1]
    got = np.empty_like(expected)
    for k, q in enumerate(q_all):
        model.update_cfg(q)
        got[k] = model.get_transform("tool", "base_link")
    position = float(np.linalg.norm(got[:, :3, 3] - expected[:, :3, 3], axis=-1).max())
    rotation = float(rotation_angle(got[:, :3, :3], expected[:, :3, :3]).max())
    assert position < 1e-9 and rotation < 1e-9, f"{robot=} {position=:.3e} {rotation=:.3e}"


@pytest.mark.parametrize("robot", robot_names())
def test_committed_urdf_states_its_physics_and_mujoco_options(robot):
    """Placeholder-inertial note, MuJoCo compiler keeping fixed links, collisions, no root inertia."""
    from lxml import etree

    text = get_robot(robot).urdf_path.read_text(encoding="utf-8")
    root = etree.fromstring(text.encode("utf-8"))
    compiler = root.find("mujoco/compiler")
    assert compiler is not None and compiler.get("fusestatic") == "false", f"{robot=}"
    assert compiler.get("discardvisual") == "false", f"{robot=}"
    assert "placeholders for visualization, not dynamics" in text, f"{robot=}"
    assert root.find("link[@name='base_link']/inertial") is None, f"{robot=}"
    collisions = root.findall("link/collision")
    assert len(collisions) >= 2 and all(
        c.find("geometry/cylinder") is not None for c in collisions
    ), f"{robot=}"

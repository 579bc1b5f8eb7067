"""The kinematic URDF (no yourdfpy) builds the same Pinocchio model as the full URDF writer."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pinocchio as pin
import pytest

from dh2urdf import ROBOTS, get_robot
from dh2urdf.kinematic_urdf import kinematic_urdf
from dh2urdf.urdf_writer import urdf_string


def _same_models(table) -> None:
    full = pin.buildModelFromXML(urdf_string(table))
    light = pin.buildModelFromXML(kinematic_urdf(table))
    assert [f.name for f in full.frames] == [f.name for f in light.frames]
    assert [f.type for f in full.frames] == [f.type for f in light.frames]
    assert list(full.names) == list(light.names)
    for a, b in zip(full.frames, light.frames):
        np.testing.assert_allclose(a.placement.homogeneous, b.placement.homogeneous, atol=1e-14)
    for a, b in zip(full.inertias, light.inertias):
        np.testing.assert_allclose(a.matrix(), b.matrix(), atol=1e-14)
    np.testing.assert_array_equal(full.lowerPositionLimit, light.lowerPositionLimit)
    np.testing.assert_array_equal(full.upperPositionLimit, light.upperPositionLimit)
    np.testing.assert_array_equal(full.velocityLimit, light.velocityLimit)
    q = np.random.default_rng(0).uniform(full.lowerPositionLimit, full.upperPositionLimit)
    d_full, d_light = full.createData(), light.createData()
    pin.framesForwardKinematics(full, d_full, q)
    pin.framesForwardKinematics(light, d_light, q)
    for a, b in zip(d_full.oMf, d_light.oMf):
        np.testing.assert_allclose(a.homogeneous, b.homogeneous, atol=1e-13)


@pytest.mark.parametrize("name", list(ROBOTS))
def test_same_model_as_the_full_writer(name):
    """Every shipped table: the same frames, joints, limits, inertias and FK."""
    _same_models(get_robot(name).load_table())


def test_same_model_with_masses_and_both_conventions():
    """Rows with mass and radius (solid-cylinder inertials) in both conventions."""
    import dataclasses

    for name in ("ur5", "panda", "pickplace3"):
        table = get_robot(name).load_table()
        rows = tuple(dataclasses.replace(r, mass=1.0 + r.index, radius=0.03) for r in table.rows)
        _same_models(dataclasses.replace(table, rows=rows))


def test_a_table_file_builds_its_model_without_yourdfpy(tmp_path):
    """kin's model of a table file imports neither yourdfpy nor trimesh."""
    path = tmp_path / "arm.toml"
    path.write_text(get_robot("ur5").table_path.read_text(encoding="utf-8"), encoding="utf-8")
    probe = (
        "import sys; from kin import load_robot, Configuration; "
        f"r = load_robot({str(path)!r}); Configuration(r).fk([0.1] * 6); "
        "print(sorted(m for m in ('yourdfpy', 'trimesh') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"

"""`dh2urdf from-urdf` keeps the body: the URDF written back from the table it writes has, at random
configurations, every visual and collision mesh of the maker's links that ride on the chain at the
maker's world pose (Pinocchio's geometry placements on both files, to 1e-9 m and rad)."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.urdf_reference import ARMS, erd

from dh2urdf import load_table
from dh2urdf.command import main

#: Random configurations per arm.
SAMPLES = 50
#: Largest difference of a mesh's pose (rotation entries [1], translation [m]).
TOLERANCE = 1e-9
#: Geometry kinds compared.
KINDS = {"visual": pin.GeometryType.VISUAL, "collision": pin.GeometryType.COLLISION}


def _maker_meshes(urdf: Path, chain_joints: list[str]) -> tuple[pin.Model, dict]:
    """The maker's model and, per kind, its meshes on the chain (or the base): (path, object)."""
    folder = urdf.resolve().parent
    dirs = [str(p) for p in [folder, *folder.parents][:6]]
    model = pin.buildModelFromUrdf(str(urdf))
    riding = {0} | {model.getJointId(name) for name in chain_joints}
    found = {}
    for kind, which in KINDS.items():
        geometry = pin.buildGeomFromUrdf(model, str(urdf), which, package_dirs=dirs)
        found[kind] = (
            geometry,
            [
                obj
                for obj in geometry.geometryObjects
                if obj.parentJoint in riding and obj.meshPath.lower().endswith((".stl", ".dae"))
            ],
        )
    return model, found


@pytest.mark.parametrize("arm", ["ur5", "panda"])
def test_meshes_of_the_table_sit_where_the_makers_do(arm, tmp_path, capsys):
    """ur5 (tool0) and panda (panda_link8, fingers off the chain): as many meshes per kind as the
    maker's links on the chain carry, each with the maker's file, scale and world pose."""
    relative, _, tip = ARMS[arm]
    urdf = erd(relative)
    table_path = tmp_path / "tables" / f"{arm}.toml"
    table_path.parent.mkdir()
    assert main(["from-urdf", str(urdf), "--tip", tip, "-o", str(table_path)]) == 0
    printed = capsys.readouterr().out
    assert " meshes" in printed, printed
    table = load_table(table_path)
    back = tmp_path / f"{arm}.urdf"
    assert main([str(table_path), "-o", str(back)]) == 0
    ours = pin.buildModelFromUrdf(str(back))
    maker, makers = _maker_meshes(urdf, list(table.joint_names))
    ours_data, maker_data = ours.createData(), maker.createData()
    rng = np.random.default_rng(11)
    lower, upper = np.maximum(table.lower, -math.pi), np.minimum(table.upper, math.pi)
    for kind, which in KINDS.items():
        # the URDF names its meshes relative to its own folder where the two share a folder below
        # the root (a clone and pytest's folders both under /tmp): Pinocchio finds a relative
        # name only through package_dirs, not from the URDF's folder
        geometry = pin.buildGeomFromUrdf(ours, str(back), which, package_dirs=[str(back.parent)])
        mine = [
            o for o in geometry.geometryObjects if o.meshPath.lower().endswith((".stl", ".dae"))
        ]
        maker_geometry, theirs = makers[kind]
        assert len(mine) == len(theirs) > 0, (kind, len(mine), len(theirs))
        assert sorted(Path(o.meshPath).resolve() for o in mine) == sorted(
            Path(o.meshPath).resolve() for o in theirs
        )
        for q in rng.uniform(lower, upper, size=(SAMPLES, table.dof)):
            full = pin.neutral(maker)
            for name, value in zip(table.joint_names, q, strict=True):
                full[maker.joints[maker.getJointId(name)].idx_q] = value
            pin.forwardKinematics(ours, ours_data, q)
            pin.forwardKinematics(maker, maker_data, full)
            left = list(theirs)
            for obj in mine:
                pose = (ours_data.oMi[obj.parentJoint] * obj.placement).homogeneous
                match = [
                    other
                    for other in left
                    if Path(other.meshPath).resolve() == Path(obj.meshPath).resolve()
                    and np.allclose(other.meshScale, obj.meshScale, rtol=0, atol=1e-12)
                    and np.abs(
                        (maker_data.oMi[other.parentJoint] * other.placement).homogeneous - pose
                    ).max()
                    < TOLERANCE
                ]
                assert match, (arm, kind, obj.name, q)
                left.remove(match[0])


def test_no_meshes_and_stdout(tmp_path, capsys):
    """--no-meshes writes the table without mesh keys (the line counts none); -o - names the
    files by absolute paths; a table in a folder beside the meshes' names them relative to it."""
    urdf = erd(ARMS["ur5"][0])
    plain = tmp_path / "plain.toml"
    assert main(["from-urdf", str(urdf), "--tip", "tool0", "--no-meshes", "-o", str(plain)]) == 0
    assert capsys.readouterr().out.endswith("m/rad)\n") and "mesh" not in plain.read_text()
    assert main(["from-urdf", str(urdf), "--tip", "tool0", "-o", "-"]) == 0
    files = [
        line.split('"')[1] for line in capsys.readouterr().out.splitlines() if "file =" in line
    ]
    assert len(files) == 14 and all(Path(f).is_absolute() and Path(f).is_file() for f in files)
    # a copy of the URDF and its meshes: a table written beside them names them relatively
    package = tmp_path / "example-robot-data" / "robots" / "ur_description"
    shutil.copytree(urdf.parent.parent / "meshes" / "ur5", package / "meshes" / "ur5")
    (package / "urdf").mkdir()
    shutil.copy(urdf, package / "urdf")
    beside = package / "ur5.toml"
    assert (
        main(["from-urdf", str(package / "urdf" / urdf.name), "--tip", "tool0", "-o", str(beside)])
        == 0
    )
    assert 'file = "meshes/ur5/visual/base.dae"' in beside.read_text()
    assert (
        str(package / "meshes" / "ur5" / "visual" / "base.dae")
        == load_table(beside).base_meshes[0].file
    )

"""A URDF's visual and collision meshes carried into the DH table read from its chain.

``dh2urdf from-urdf`` gives a table the maker's body: every ``<mesh>`` of a ``<visual>`` or
``<collision>`` of a link that rides rigidly on the chain (the chain's links, the links fixed to
them such as a UR's ``ee_link`` or a flange, the links fixed to the base) becomes a mesh of the
table (:mod:`dh2urdf.link_meshes`): of row ``i`` when joint ``i`` is the chain joint nearest above
the link, of ``[[base_mesh]]`` when the link rides on the base link. Its origin is re-expressed
in that DH frame at q = 0, where the table's frames and the URDF's links are placed by the same
forward kinematics (:func:`dh2urdf.urdf_to_dh.check_table`), so at every q the mesh sits where
the maker's does.

Pinocchio reads the geometry (its ``buildGeomFromUrdfString``: ``package://`` names found in the
URDF's folder and its parents, the scale, the origin on the parent joint), so the file names and
placements are those every Pinocchio user gets. Left out, and counted: the meshes of links on a
joint off the chain (a gripper's fingers), primitive shapes (boxes, cylinders, spheres: a table
names meshes), and meshes of a format a table does not take.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .dh_table import DHTable, dh_link_transform
from .link_meshes import MESH_SUFFIXES, LinkMesh
from .output_text import counted
from .urdf_chain import UrdfChain

__all__ = ["CarriedMeshes", "PACKAGE_LEVELS", "carry_meshes"]

#: Folders above the URDF searched for ``package://NAME/...`` (as kin's readers search).
PACKAGE_LEVELS = 6
#: Two meshes with the same file, scale and origins this close are one, used for both [m, 1].
SAME = 1e-12


@dataclass(frozen=True)
class CarriedMeshes:
    """The table with the URDF's meshes, and what was left out.

    Attributes:
        table: The table, its rows' and base's meshes set.
        carried: Meshes the table names (one used for visual and collision counts once).
        left_out: One phrase per kind left out (``"2 meshes of links on joints off the chain"``).
    """

    table: DHTable
    carried: int
    left_out: tuple[str, ...]


def carry_meshes(chain: UrdfChain, table: DHTable) -> CarriedMeshes:
    """``table`` (read from ``chain``) with the meshes of the URDF's links that ride on the chain.

    Raises:
        OSError: Pinocchio cannot read the URDF's geometry (a mesh not found, not readable).
    """
    import pinocchio as pin

    folder = Path(chain.path).resolve().parent
    package_dirs = [str(p) for p in [folder, *folder.parents][:PACKAGE_LEVELS]]
    model = pin.buildModelFromXML(chain.text)
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    base_joint = model.frames[model.getFrameId(chain.base, pin.FrameType.BODY)].parentJoint
    row_of = {model.getJointId(row.name): row.index for row in table.rows}
    row_of[base_joint] = 0
    base_frame = model.frames[model.getFrameId(chain.base, pin.FrameType.BODY)]
    T_base_world = (data.oMi[base_joint] * base_frame.placement).inverse()  # at q = 0
    frames = _dh_frames(table)
    found: dict[int, list[LinkMesh]] = {}
    off_chain = primitives = other_format = 0
    try:
        kinds = [
            (use, pin.buildGeomFromUrdfString(model, chain.text, kind, package_dirs=package_dirs))
            for use, kind in (
                ("visual", pin.GeometryType.VISUAL),
                ("collision", pin.GeometryType.COLLISION),
            )
        ]
    except (RuntimeError, ValueError) as err:
        reason = " ".join(str(err).split())[:200]
        raise OSError(
            f"{chain.path}: cannot read its meshes ({reason}); --no-meshes writes the table "
            "without them"
        ) from err
    for use, geometry in kinds:
        for obj in geometry.geometryObjects:
            path = obj.meshPath
            if not path or path in ("BOX", "SPHERE", "CYLINDER", "CAPSULE"):
                primitives += 1
                continue
            if Path(path).suffix.lower() not in MESH_SUFFIXES:
                other_format += 1
                continue
            row = row_of.get(obj.parentJoint)
            if row is None:
                off_chain += 1
                continue
            T_base_mesh = T_base_world * data.oMi[obj.parentJoint] * obj.placement
            origin = np.linalg.inv(frames[row]) @ T_base_mesh.homogeneous
            scale = tuple(float(v) for v in obj.meshScale)
            mesh = LinkMesh(str(Path(path).resolve()), origin, scale, use)  # type: ignore[arg-type]
            found.setdefault(row, []).append(mesh)
    merged = {row: _merged(meshes) for row, meshes in found.items()}
    rows = tuple(
        dataclasses.replace(row, meshes=tuple(merged.get(row.index, ()))) for row in table.rows
    )
    carried = dataclasses.replace(table, rows=rows, base_meshes=tuple(merged.get(0, ())))
    left_out = [
        f"{counted(count, noun, plural)}{what}"
        for count, noun, plural, what in (
            (off_chain, "mesh", "meshes", " of links on joints off the chain"),
            (primitives, "primitive shape", None, " (a table names meshes)"),
            (other_format, "mesh", "meshes", f" not in {', '.join(MESH_SUFFIXES)}"),
        )
        if count
    ]
    total = sum(len(meshes) for meshes in merged.values())
    return CarriedMeshes(carried, total, tuple(left_out))


def _dh_frames(table: DHTable) -> list[np.ndarray]:
    """``T_base_frame_i`` of DH frames 0..n at q = 0 (4x4, [m])."""
    frames = [np.asarray(table.T_world_base, dtype=float)]
    for row in table.rows:
        theta, d = row.dh_values(0.0)
        step = dh_link_transform(table.convention, row.a, row.alpha, d, theta)
        frames.append(frames[-1] @ step)
    return frames


def _merged(meshes: list[LinkMesh]) -> list[LinkMesh]:
    """The meshes, a visual and a collision mesh that are the same one written once as "both"."""
    out: list[LinkMesh] = []
    for mesh in meshes:
        twin = next(
            (
                i
                for i, kept in enumerate(out)
                if kept.use == "visual"
                and mesh.use == "collision"
                and kept.file == mesh.file
                and np.allclose(kept.scale, mesh.scale, rtol=0.0, atol=SAME)
                and np.allclose(kept.origin, mesh.origin, rtol=0.0, atol=SAME)
            ),
            None,
        )
        if twin is None:
            out.append(mesh)
        else:
            out[twin] = dataclasses.replace(out[twin], use="both")
    return out

"""The calibrated arm as files: a DH table (.toml) and a URDF whose root is the measurement frame.

The table takes the fitted rows, ``[base]`` = DH frame 0 in the measurement frame and ``[tool]``
= the measured point (marker 1) or frame. Hayati's ``beta`` (the tilt of a joint axis toward a
parallel neighbour, :mod:`kin.calibration.parameters`) has no key in the table format, so a
calibration with such a tilt is written as a URDF only (the table would need a ``d`` of hundreds
of meters to express a hundredth of a degree). The URDF is the table's
(:func:`dh2urdf.urdf_writer.urdf_elements`: the same links, visuals and limits) with the tilts in
the joint origins, the root ``base_link`` named ``measurement_frame`` and the measured point(s)
``measured_point`` (``measured_point_<k>`` for several markers): its FK alone predicts the
measurements.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dh2urdf import DHTable
from dh2urdf.transforms import rot_x, rot_z, translation
from dh2urdf.urdf_elements import Joint, Link, robot_xml

from .calibration import Calibration
from .exceptions import CalibrationError

ROOT = "measurement_frame"
POINT = "measured_point"


def _rot_y(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    out = np.eye(4)
    out[0, 0] = out[2, 2] = c
    out[0, 2], out[2, 0] = s, -s
    return out


def tilts(calibration: Calibration) -> dict[int, float]:
    """Fitted ``beta`` per 0-based row [rad] (rows with a nonzero tilt)."""
    model, x = calibration.model, calibration.x
    found = {i: model.row_values(x, i)["beta"] for i in model.beta_rows}
    return {i: b for i, b in found.items() if b != 0.0}


def calibrated_table(calibration: Calibration, allow_tilts: bool = False) -> DHTable:
    """The calibrated DH table in the measurement frame (SI units).

    Args:
        calibration: The calibration.
        allow_tilts: Leave out the ``beta`` tilts instead of refusing (for the URDF, which adds them).

    Raises:
        CalibrationError: A fitted tilt ``beta`` the table format cannot hold.
    """
    model, x, table = calibration.model, calibration.x, calibration.table
    tilted = tilts(calibration)
    if tilted and not allow_tilts:
        tilted_rows = ", ".join(
            f"{table.rows[i].name} {np.degrees(b):+.4f} deg" for i, b in tilted.items()
        )
        raise CalibrationError(
            f"the fit tilts joint axes toward their parallel neighbours (beta: {tilted_rows}), which a DH "
            "table cannot hold without exploding d: write the URDF (-o FILE.urdf)"
        )
    rows = []
    for i, row in enumerate(table.rows):
        v = model.row_values(x, i)
        rows.append(
            dataclasses.replace(row, a=v["a"], alpha=v["alpha"], d=v["d"], theta=v["theta"])
        )
    return dataclasses.replace(
        table,
        name=f"{table.name}_calibrated",
        description=f"{table.description}, calibrated",
        source=f"{table.source}; calibrated from {calibration.measurements.path} "
        f"({calibration.measurements.count} rows, dh2urdf calibrate)",
        rows=tuple(rows),
        T_world_base=model.T_measurement_base(x),
        T_last_tool=model.T_last_tool(x),
        path=None,
        drives=(),
    )


def _rpy(rotation: np.ndarray) -> tuple[float, float, float]:
    """URDF roll-pitch-yaw of a rotation matrix [rad] (scipy's extrinsic xyz)."""
    from scipy.spatial.transform import Rotation

    roll, pitch, yaw = Rotation.from_matrix(rotation).as_euler("xyz")
    return float(roll), float(pitch), float(yaw)


def _tilted(joint: Joint, tilt: np.ndarray) -> Joint:
    return dataclasses.replace(joint, origin=joint.origin @ tilt)


def calibrated_urdf(calibration: Calibration) -> str:
    """URDF text of the calibrated arm: root ``measurement_frame``, last link ``measured_point``."""
    from dh2urdf.urdf_writer import MUJOCO_COMPILER, urdf_elements

    table = calibrated_table(calibration, allow_tilts=True)
    robot = urdf_elements(table)
    joints = list(robot.joints)
    for i, beta in tilts(calibration).items():
        row = table.rows[i]
        if table.convention == "standard":
            k = next(j for j, joint in enumerate(joints) if joint.name == f"frame{i + 1}_joint")
            joints[k] = _tilted(joints[k], _rot_y(beta))
        else:
            k = next(j for j, joint in enumerate(joints) if joint.name == row.name)
            origin = (
                rot_x(row.alpha)
                @ _rot_y(beta)
                @ translation(x=row.a)
                @ rot_z(row.theta)
                @ translation(z=row.d)
            )
            joints[k] = dataclasses.replace(joints[k], origin=origin)
    markers = calibration.model.markers
    names = {"base_link": ROOT, "tool": POINT if markers <= 1 else f"{POINT}_1"}
    links = [
        dataclasses.replace(link, name=names.get(link.name, link.name)) for link in robot.links
    ]
    joints = [
        dataclasses.replace(
            j, parent=names.get(j.parent, j.parent), child=names.get(j.child, j.child)
        )
        for j in joints
    ]
    last = f"frame{table.dof}"
    for k in range(2, markers + 1):
        origin = np.eye(4)
        origin[:3, 3] = calibration.model.marker(calibration.x, k)
        links.append(Link(name=f"{POINT}_{k}"))
        joints.append(
            Joint(
                name=f"{POINT}_{k}_joint",
                type="fixed",
                parent=last,
                child=f"{POINT}_{k}",
                origin=origin,
            )
        )
    body = robot_xml(
        dataclasses.replace(robot, links=tuple(links), joints=tuple(joints)), MUJOCO_COMPILER
    )
    header = (
        f"<!-- Calibrated by dh2urdf calibrate from the DH table '{calibration.table.name}' and "
        f"{calibration.measurements.count} measured rows.\n"
        f"     Root: {ROOT} (the tracker's frame); last link: {names['tool']} (the measured point).\n"
        "     Units: meters, radians. -->\n"
    )
    return '<?xml version="1.0" encoding="utf-8"?>\n' + header + body

"""The calibrated arm as files: a DH table (.toml) and a URDF whose root is the measurement frame.

The table takes the fitted rows, Hayati's ``beta`` included (the tilt of a joint axis toward a
parallel neighbour, :mod:`kin.calibration.parameters`: the table's ``beta`` key, in the same place
of the row's product, :mod:`dh2urdf.dh_table`), ``[base]`` = DH frame 0 in the measurement frame
and ``[tool]`` = the measured point (marker 1) or frame. The URDF is the table's
(:func:`dh2urdf.urdf_writer.urdf_elements`: the same links, visuals and limits, the tilts in the
joint origins) with the root ``base_link`` named ``measurement_frame`` and the measured point(s)
``measured_point`` (``measured_point_<k>`` for several markers): its FK alone predicts the
measurements.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dh2urdf import DHTable
from dh2urdf.urdf_elements import Joint, Link, robot_xml

from .calibration import Calibration

ROOT = "measurement_frame"
POINT = "measured_point"


def tilts(calibration: Calibration) -> dict[int, float]:
    """Fitted ``beta`` per 0-based row [rad] (rows with a nonzero tilt)."""
    model, x = calibration.model, calibration.x
    found = {i: model.row_values(x, i)["beta"] for i in model.beta_rows}
    return {i: b for i, b in found.items() if b != 0.0}


def calibrated_table(calibration: Calibration) -> DHTable:
    """The calibrated DH table in the measurement frame (SI units), its rows' tilts included."""
    model, x, table = calibration.model, calibration.x, calibration.table
    rows = []
    for i, row in enumerate(table.rows):
        v = model.row_values(x, i)
        rows.append(
            dataclasses.replace(
                row, a=v["a"], alpha=v["alpha"], d=v["d"], theta=v["theta"], beta=v["beta"]
            )
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


def calibrated_urdf(calibration: Calibration) -> str:
    """URDF text of the calibrated arm: root ``measurement_frame``, last link ``measured_point``."""
    from dh2urdf.urdf_writer import MUJOCO_COMPILER, urdf_elements

    table = calibrated_table(calibration)
    robot = urdf_elements(table)  # the rows' tilts in the joint origins (dh2urdf.urdf_writer)
    joints = list(robot.joints)
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

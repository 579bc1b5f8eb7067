"""A general 6R arm with a mimic joint as URDF text, and Pinocchio's FK of it with the mimic joint
set by hand: the independent reference of the mimic tests.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

#: (name, origin xyz [m], origin rpy [rad], axis, limits [rad]) of a general 6R arm, with a
#: mimic joint "j3m" right after j3 (inserted by _urdf).
JOINTS = [
    ("j1", (0.0, 0.0, 0.33), (0.0, 0.0, 0.1), (0.0, 0.0, 1.0), (-2.8, 2.8)),
    ("j2", (0.05, 0.02, 0.1), (0.2, 0.0, 0.0), (0.0, 1.0, 0.0), (-2.0, 2.0)),
    ("j3", (0.0, 0.0, 0.4), (0.0, 0.1, 0.0), (0.0, 1.0, 0.0), (-2.5, 2.5)),
    ("j3m", (0.12, 0.0, 0.03), (0.0, 0.0, 0.3), (0.0, 0.6, 0.8), (-2.0, 2.0)),
    ("j4", (0.3, 0.01, 0.0), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (-3.0, 3.0)),
    ("j5", (0.1, 0.0, 0.0), (0.1, 0.0, 0.0), (0.0, 1.0, 0.0), (-2.0, 2.0)),
    ("j6", (0.08, 0.0, 0.02), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (-3.0, 3.0)),
]
TIP_ORIGIN = ((0.05, 0.0, 0.0), (0.0, 0.2, 0.0))
OFFSET = 0.3


def _urdf(multiplier: float, leader: str = "j3") -> str:
    links = ["base"] + [f"l{i}" for i in range(1, len(JOINTS) + 1)] + ["tip"]
    parts = ['<robot name="mimic6r">'] + [f'<link name="{name}"/>' for name in links]
    for i, (name, xyz, rpy, axis, (low, high)) in enumerate(JOINTS):
        mimic = (
            f'<mimic joint="{leader}" multiplier="{multiplier}" offset="{OFFSET}"/>'
            if name == "j3m"
            else ""
        )
        parts.append(
            f'<joint name="{name}" type="revolute"><parent link="{links[i]}"/>'
            f'<child link="{links[i + 1]}"/><origin xyz="{" ".join(map(str, xyz))}" '
            f'rpy="{" ".join(map(str, rpy))}"/><axis xyz="{" ".join(map(str, axis))}"/>'
            f'<limit lower="{low}" upper="{high}" effort="10" velocity="2"/>{mimic}</joint>'
        )
    xyz, rpy = TIP_ORIGIN
    parts.append(
        f'<joint name="flange" type="fixed"><parent link="{links[-2]}"/><child link="tip"/>'
        f'<origin xyz="{" ".join(map(str, xyz))}" rpy="{" ".join(map(str, rpy))}"/></joint>'
    )
    return "\n".join([*parts, "</robot>"])


def _in_limits(q: np.ndarray, multiplier: float) -> bool:
    values = [*q[:3], multiplier * q[2] + OFFSET, *q[3:]]
    return all(lo <= v <= hi for v, (*_, (lo, hi)) in zip(values, JOINTS, strict=True))


def _pinocchio_mimic_fk(path, q: np.ndarray) -> np.ndarray:
    """``T_base_tip`` by Pinocchio's model of the file built with mimic joints (q: the six
    independent joints, the model's own order)."""
    model = pin.buildModelFromUrdf(str(path), mimic=True)
    data = model.createData()
    pin.framesForwardKinematics(model, data, np.asarray(q, dtype=float))
    return data.oMf[model.getFrameId("tip")].homogeneous

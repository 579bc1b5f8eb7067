"""Paper 004 (scorbot): the home pose of its 0T5 at all-zero joint angles, in mm.

The paper's 0T5 at q = 0 gives p = (a1 + a2 + a3 + d5, 0, d1) = (603, 0, 349) mm, approach axis
a = (1, 0, 0), normal n = (0, 0, -1), sliding o = (0, 1, 0). The symbolic 0T5 (no printed number) is
also evaluated at one other configuration against ours.
"""

from __future__ import annotations

import math

import numpy as np

from kin.robot_model import load_robot

from ._robots import tool_pose_deg
from .printed import vector
from .report import Row, Section, Verdict

_MM = 0.001
#: Table 1 [mm].
_A1, _A2, _A3, _D1, _D5 = 16.0, 221.0, 221.0, 349.0, 145.0
#: A configuration away from the singular home [deg], inside the ranges of Table 3.
_Q_CHECK = (30.0, -20.0, 40.0, 10.0, 50.0)


def paper_0t5(q_deg: tuple[float, ...]) -> np.ndarray:
    """The paper's symbolic 0T5 (section III), evaluated as printed: 4x4, [mm]."""
    t1, t2, t3, t4, t5 = (math.radians(v) for v in q_deg)
    c, s = math.cos, math.sin
    c234, s234 = c(t2 + t3 + t4), s(t2 + t3 + t4)
    reach = _A1 + _A2 * c(t2) + _A3 * c(t2 + t3) + c234 * _D5
    return np.array(
        [
            [
                -s(t1) * s(t5) - c(t1) * s234 * c(t5),
                -s(t1) * c(t5) + c(t1) * s234 * s(t5),
                c(t1) * c234,
                c(t1) * reach,
            ],
            [
                c(t1) * s(t5) - s(t1) * s234 * c(t5),
                c(t1) * c(t5) + s(t1) * s234 * s(t5),
                s(t1) * c234,
                s(t1) * reach,
            ],
            [-c234 * c(t5), c234 * s(t5), -s234, _D1 - _A2 * s(t2) - _A3 * s(t2 + t3) - s234 * _D5],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


def _row(
    label: str, paper: np.ndarray, ours: np.ndarray, places: int, unit: str, tol: float
) -> Row:
    """One vector row; ``unit`` is ``"mm"`` or ``"-"`` (direction cosines), ``tol`` in that unit."""
    error = float(np.max(np.abs(ours - paper)))
    verdict: Verdict = "reproduced" if error <= tol else "not reproduced"
    return Row(
        label,
        vector(list(paper), places, unit),
        vector(list(ours), places, unit),
        f"max {error:.1e} {unit}",
        verdict,
        "" if verdict == "reproduced" else f"differs by {error:.3g} {unit}",
    )


def scorbot_sections() -> list[Section]:
    """The section of paper 004, home pose."""
    robot = load_robot("scorbot")
    home = tool_pose_deg(robot, [0.0] * robot.nq)
    paper_home = paper_0t5((0.0,) * 5)
    rows = [
        _row("home, q = 0, position p", paper_home[:3, 3], home.translation / _MM, 0, "mm", 0.5),
        _row("home, q = 0, approach axis a", paper_home[:3, 2], home.rotation[:, 2], 0, "-", 1e-9),
        _row("home, q = 0, normal axis n", paper_home[:3, 0], home.rotation[:, 0], 0, "-", 1e-9),
        _row("home, q = 0, sliding axis o", paper_home[:3, 1], home.rotation[:, 1], 0, "-", 1e-9),
    ]
    check = paper_0t5(_Q_CHECK)
    pose = tool_pose_deg(robot, _Q_CHECK)
    label = f"symbolic 0T5 evaluated at q = ({', '.join(f'{v:g}' for v in _Q_CHECK)}) deg"
    rows.append(_row(f"{label}, position p", check[:3, 3], pose.translation / _MM, 4, "mm", 1e-6))
    rows.append(
        _row(
            f"{label}, rotation (columns n, o, a)",
            check[:3, :3].T.reshape(-1),
            pose.rotation.T.reshape(-1),
            4,
            "-",
            1e-9,
        )
    )
    intro = (
        "Tool pose of scorbot through Pinocchio (kin) against the paper's 0T5 (Table 1 lengths "
        "[mm], joint 4 "
        "with its +90 deg offset); difference = max |ours - paper|; '-' marks direction cosines "
        "(no unit)."
    )
    notes = (
        "p = (a1 + a2 + a3 + d5, 0, d1) = (16 + 221 + 221 + 145, 0, 349) mm: the arm stretched "
        "along x with "
        "the tool pointing along x.",
        "The last two rows evaluate the printed symbolic 0T5 (it has no printed number) away from "
        "home: it "
        "agrees with Table 1 through kin there too.",
    )
    return [Section("004 home pose: scorbot forward kinematics", intro, tuple(rows), notes)]

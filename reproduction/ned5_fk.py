"""Paper 001 (ned5): the home pose (43.8, 0, 1) cm at q = 0, and the reading of its Table 1.

Table 1 is headed alpha_{i-1}, a_{i-1} (modified DH, Craig), but the paper's transform (20) is the
standard one and its home (a2 + a3 + a4 + d5, 0, d1) only follows from the standard reading,
which is our table. The modified reading of the same rows is evaluated through kin for comparison.
"""

from __future__ import annotations

from dh2urdf import get_robot
from kin.robot_model import load_robot

from ._robots import tool_position_deg, variant
from .printed import agreement, vector
from .report import Row, Section

_CM = 0.01
#: The paper's home [cm], text and Fig. 10 (MATLAB prints Pos_X 43.8, Pos_Y -1.1389e-15, Pos_Z 1).
_HOME = ("43.8", "0", "1")


def ned5_sections() -> list[Section]:
    """The section of paper 001, home pose."""
    ours = load_robot("ned5")
    modified = variant(get_robot("ned5").load_table(), "ned5_modified", convention="modified")
    zero = [0.0] * ours.nq
    standard_home = tool_position_deg(ours, zero, _CM)
    modified_home = tool_position_deg(modified, zero, _CM)
    paper = f"({', '.join(_HOME)}) cm"
    home_ok = all(
        agreement(float(v), t) == "rounded" for v, t in zip(standard_home, _HOME, strict=True)
    )
    modified_ok = all(
        agreement(float(v), t) == "rounded" for v, t in zip(modified_home, _HOME, strict=True)
    )
    target = [float(t) for t in _HOME]
    rows = (
        Row(
            "home, q = 0, Table 1 read as standard DH (our table)",
            paper,
            vector(list(standard_home), 1, "cm"),
            vector([a - b for a, b in zip(standard_home, target, strict=True)], 4, "cm"),
            "reproduced" if home_ok else "not reproduced",
            "" if home_ok else "the standard reading should give the home; check the table",
        ),
        Row(
            "home, q = 0, Table 1 read as its header says (modified DH: alpha_{i-1}, a_{i-1})",
            paper,
            vector(list(modified_home), 1, "cm"),
            vector([a - b for a, b in zip(modified_home, target, strict=True)], 4, "cm"),
            "reproduced" if modified_ok else "not reproduced",
            "the header's convention is a mistake of the paper: read as modified DH, the rows "
            "give another arm"
            if not modified_ok
            else "",
        ),
    )
    intro = (
        "Tool position [cm] of ned5 through Pinocchio (kin) at q = 0 (joint 4 carries the +90 deg "
        "offset of "
        "Table 1); difference = ours - paper."
    )
    notes = (
        "The paper's home is a2 + a3 + a4 + d5 = 10.5 + 14.7 + 7.6 + 11 = 43.8 cm along x at "
        "height d1 = 1 cm; "
        "its transform (20) is the standard DH matrix, so the standard reading is the paper's own.",
    )
    return [Section("001 home pose: ned5 forward kinematics", intro, rows, notes)]

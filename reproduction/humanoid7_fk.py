"""Paper 000 (humanoid7), Tables II-VIII: tool position for 7 cases, 4 columns each, in cm.

The cases print DH angles: Case 1 (0, -90, 90, 0, 0, 90, 0) deg is the Table I offsets, the arm
stretched along x, which is our q = 0. So q = angle - offset. Our table has Table I's
L2 = 28.774 cm; the paper's equations (5)-(7) and home 86.33 cm use 28.7 cm, and some columns use
28.77 cm. Every cell is compared with our robot, then with the readings that could explain it.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from dh2urdf import get_robot
from kin.robot_model import RobotModel, load_robot

from ._robots import dh_angles_to_q, tool_position_deg, variant
from .printed import agreement, at_printed, decimals, fmt
from .report import Row, Section, Verdict

_CM = 0.01
_COLUMNS = ("DH solution", "UV solution", "Peter Corke", "RoboAnalyzer")
_AXES = ("X", "Y", "Z")

#: (table number, case DH angles [deg]) as printed.
_CASES: tuple[tuple[str, tuple[float, ...]], ...] = (
    ("II", (0, -90, 90, 0, 0, 90, 0)),
    ("III", (-90, -60, -30, 0, 30, 60, 90)),
    ("IV", (-30, 0, -60, 90, 60, -90, 30)),
    ("V", (30, -60, 0, 90, 60, -90, -30)),
    ("VI", (0, 90, -60, 60, -90, -30, 30)),
    ("VII", (90, 60, -90, -30, 30, -60, 0)),
    ("VIII", (-60, 60, -30, -90, 90, 0, 30)),
)

#: Printed cells [cm]: per case, rows X, Y, Z; per row the four columns of _COLUMNS.
_PRINTED: tuple[tuple[tuple[str, str, str, str], ...], ...] = (
    (("86.33", "86.33", "86.33", "86.33"), ("0", "0", "0", "0"), ("0", "0", "0", "0")),
    (
        ("-19.94", "-19.94", "-19.94", "-19.94"),
        ("-58.788", "-58.788", "-58.788", "-58.8489"),
        ("-28.37", "-28.40", "-28.370", "-28.405"),
    ),
    (
        ("1.521", "1.521", "1.521", "1.5213"),
        ("-14.527", "-14.527", "-14.527", "-14.527"),
        ("-20.065", "-20.065", "-20.066", "-20.135"),
    ),
    (
        ("29.20", "29.25", "29.201", "29.2537"),
        ("22.615", "22.645", "22.615", "22.6468"),
        ("-27.99", "-28.03", "-27.995", "-28.0305"),
    ),
    (
        ("-37.387", "-37.457", "-37.287", "-37.4517"),
        ("-2.759", "-2.759", "-2.760", "-2.759"),
        ("18.861", "18.861", "18.862", "18.8618"),
    ),
    (
        ("-12.863", "-12.863", "-12.863", "-12.8632"),
        ("-17.052", "-17.112", "-17.052", "-17.1129"),
        ("-21.172", "-21.207", "-21.173", "-21.207"),
    ),
    (
        ("-4.530", "-4.530", "-4.530", "-4.53"),
        ("5.9766", "5.9766", "5.9766", "5.976"),
        ("-47.873", "-47.877", "-47.843", "-47.877"),
    ),
)

#: What the computed values suggest for the cells no reading gives: (case, axis, column).
_MISPRINTS: dict[tuple[int, str, int], str] = {
    (5, "X", 2): "0.100 cm off the L2 = 28.7 cm value the other cells of this column follow: "
    "one misprinted digit",
    (5, "X", 3): "the L2 = 28.77 cm value with its last two digits swapped",
    (
        4,
        "Y",
        3,
    ): "X and Z of this case are the L2 = 28.77 cm values to 4 decimals: one misprinted digit",
    (7, "Z", 0): "X and Y of this case are the L2 = 28.77 cm values: likely a misprint of -47.877",
}

_OURS = "ours"
_SHORT = {_OURS: "ours:", "28.7": "L2 = 28.7:", "28.77": "L2 = 28.77:"}


@dataclass(frozen=True)
class _Reading:
    """A way of computing the table: a robot and how the case angles become joint values."""

    key: str
    label: str
    robot: RobotModel
    angles_are_dh: bool = True
    radians: bool = False

    def positions(self) -> list[np.ndarray]:
        """Tool position [cm] of each case."""
        out = []
        for _, angles in _CASES:
            values = [np.degrees(a) for a in angles] if self.radians else list(angles)
            q = dh_angles_to_q(self.robot, values) if self.angles_are_dh else values
            out.append(tool_position_deg(self.robot, q, _CM))
        return out


@dataclass(frozen=True)
class _Cell:
    case: int
    axis: int
    column: int
    printed: str
    values: dict[str, float]
    key: str | None
    how: str | None


def _readings() -> list[_Reading]:
    ours = load_robot("humanoid7")
    table = get_robot("humanoid7").load_table()
    return [
        _Reading(_OURS, "ours (L2 = 28.774 cm, Table I)", ours),
        _Reading(
            "28.7",
            "L2 = 28.7 cm (eqs. (5)-(7), home 86.33 cm)",
            variant(table, "l2_28p7", row3={"d": 0.287}),
        ),
        _Reading("28.77", "L2 = 28.77 cm", variant(table, "l2_28p77", row3={"d": 0.2877})),
    ]


def _explored(table_robot: RobotModel, lengths: dict[str, RobotModel]) -> list[_Reading]:
    table = table_robot.table
    out = [
        _Reading(
            f"B{k}",
            f"q = printed angle with Table I offsets added, L2 = {k} cm",
            r,
            angles_are_dh=False,
        )
        for k, r in lengths.items()
    ]
    out += [
        _Reading(f"rad{k}", f"printed angles taken as radians, L2 = {k} cm", r, radians=True)
        for k, r in lengths.items()
    ]
    uv = variant(table, "uv_eqs", row1={"a": 0.0}, row3={"d": 0.0}, row5={"d": 0.0})
    out.append(
        _Reading(
            "uv",
            "the printed UV eqs. (20)-(22), which keep only the L4 terms (L1 = L2 = L3 = 0)",
            uv,
        )
    )
    return out


def _classify(case: int, axis: int, column: int, printed: str, values: dict[str, float]) -> _Cell:
    if agreement(values[_OURS], printed) == "rounded":
        return _Cell(case, axis, column, printed, values, _OURS, "rounded")
    for how in ("rounded", "truncated"):
        for key in values:
            if agreement(values[key], printed) == how:
                return _Cell(case, axis, column, printed, values, key, how)
    return _Cell(case, axis, column, printed, values, None, None)


def _depends_on_l2(cell: _Cell) -> bool:
    places = decimals(cell.printed)
    return fmt(cell.values["28.7"], places) != fmt(cell.values["28.77"], places)


def _row(cell: _Cell, labels: dict[str, str], usual: dict[int, str]) -> Row:
    table, _ = _CASES[cell.case - 1]
    places = decimals(cell.printed)
    ours = cell.values[_OURS]
    label = f"Table {table} (case {cell.case}), {_AXES[cell.axis]}, {_COLUMNS[cell.column]}"
    verdict: Verdict
    if cell.key == _OURS and cell.how == "rounded":
        verdict, reason = "reproduced", ""
    elif cell.key == _OURS:
        verdict = "flagged"
        reason = f"printed truncated, not rounded: ours is {fmt(ours, places + 2)} cm"
    elif cell.key is not None:
        verdict = "flagged"
        value = cell.values[cell.key]
        reason = f"{labels[cell.key]} gives {fmt(value, places + 2)} cm"
        if cell.how == "truncated":
            reason += ", truncated"
        other = usual[cell.column]
        if _depends_on_l2(cell) and cell.key != other:
            here = fmt(cell.values[other], places + 2)
            reason += f"; the rest of this column follows {labels[other]} ({here} cm here)"
    else:
        verdict = "not reproduced"
        tried = ", ".join(f"{_SHORT[k]} {fmt(v, places + 2)}" for k, v in cell.values.items())
        reason = f"no reading gives it ({tried} cm)"
        hint = _MISPRINTS.get((cell.case, _AXES[cell.axis], cell.column))
        if hint:
            reason += f"; {hint}"
    return Row(
        label=label,
        paper=f"{cell.printed} cm",
        ours=f"{at_printed(ours, cell.printed)} cm",
        difference=f"{fmt(ours - float(cell.printed), max(places, 3))} cm",
        verdict=verdict,
        reason=reason,
    )


def _matches(reading: _Reading) -> list[str]:
    """Cells a reading gives (rounded or truncated), as ``case/axis/column``."""
    hits = []
    for case, position in enumerate(reading.positions(), start=1):
        for axis in range(3):
            for column in range(4):
                printed = _PRINTED[case - 1][axis][column]
                if agreement(float(position[axis]), printed) is not None:
                    hits.append(f"{case}{_AXES[axis]}/{_COLUMNS[column].split()[0]}")
    return hits


def humanoid7_sections() -> list[Section]:
    """The section of paper 000, Tables II-VIII."""
    readings = _readings()
    labels = {r.key: r.label for r in readings}
    positions = {r.key: r.positions() for r in readings}
    cells = [
        _classify(
            case,
            axis,
            column,
            _PRINTED[case - 1][axis][column],
            {k: float(p[case - 1][axis]) for k, p in positions.items()},
        )
        for case in range(1, len(_CASES) + 1)
        for axis in range(3)
        for column in range(4)
    ]
    # The length each column follows, from the cells that tell 28.7 from 28.77 cm apart.
    usual = {}
    for column in range(4):
        keys = Counter(
            c.key
            for c in cells
            if c.column == column and c.key in ("28.7", "28.77") and _depends_on_l2(c)
        )
        usual[column] = keys.most_common(1)[0][0]
    rows = tuple(_row(cell, labels, usual) for cell in cells)

    notes = []
    for column, name in enumerate(_COLUMNS):
        counts = Counter(c.key or "none" for c in cells if c.column == column)
        truncated = sum(1 for c in cells if c.column == column and c.how == "truncated")
        notes.append(
            f"{name} column: {counts[_OURS]} of 21 cells given by ours (L2-independent or "
            "truncated), "
            f"{counts['28.7']} only by L2 = 28.7 cm, {counts['28.77']} only by L2 = 28.77 cm, "
            f"{counts['none']} by no reading; {truncated} cells match only truncated, "
            f"not rounded. It follows L2 = {usual[column]} cm where the length matters."
        )
    home = positions[_OURS][0][0], positions["28.7"][0][0], positions["28.77"][0][0]
    notes.append(
        f"Home (Table II, X): ours {fmt(home[0], 3)} cm = 9.65 + 28.774 + 28.04 + 19.94; the "
        "printed 86.33 cm is "
        f"L2 = 28.7 cm ({fmt(home[1], 3)} cm), which every column prints, including RoboAnalyzer, "
        "whose "
        f"other cells follow L2 = 28.77 cm ({fmt(home[2], 3)} cm)."
    )
    lengths = {"28.774": readings[0].robot, "28.7": readings[1].robot, "28.77": readings[2].robot}
    for reading in _explored(readings[0].robot, lengths):
        hits = _matches(reading)
        nonzero = [h for h in hits if float(_cell_text(h)) != 0.0]
        notes.append(
            f"Explored, rejected: {reading.label}: gives {len(hits)} of 84 cells"
            + (f", the nonzero ones: {', '.join(nonzero)}" if nonzero else "")
            + (
                " (case 2 X is -L4 = -19.94 cm, which these L4-only equations keep)"
                if reading.key == "uv"
                else ""
            )
            + (", all of them zeros" if hits and not nonzero else "")
            + f" (case 1: {', '.join(fmt(v, 3) for v in reading.positions()[0])} cm)."
        )
    intro = (
        "Tool position [cm] of humanoid7 through Pinocchio (kin), at q = printed angle - Table I "
        "offset "
        "(the cases print DH angles: case 1 is the stretched pose, our q = 0). 'ours' is our table "
        "(L2 = 28.774 cm as in Table I), at the paper's printed decimals; difference = ours - "
        "paper. "
        "A cell ours does not give is tried with L2 = 28.7 cm (the paper's eqs. (5)-(7) and home) "
        "and "
        "L2 = 28.77 cm (variant tables through kin), rounded first, then truncated."
    )
    return [Section("000 Tables II-VIII: humanoid7 forward kinematics", intro, rows, tuple(notes))]


def _cell_text(hit: str) -> str:
    case, axis, column = int(hit[0]), _AXES.index(hit[1]), hit.split("/")[1]
    index = [c.split()[0] for c in _COLUMNS].index(column)
    return _PRINTED[case - 1][axis][index]

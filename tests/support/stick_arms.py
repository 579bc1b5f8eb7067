"""Shipped arms as the DH writer's 1 cm sticks (their housings left out): bodies a test computes by
hand, for the collision tests that check the checker rather than the arm's volume."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

from dh2urdf.robots import get_robot
from kin import RobotModel, load_robot
from kin.robot_model import robot_from_table

#: A ``[[joints.housing]]`` table of a shipped table file, as the shipped files write it.
_HOUSING = re.compile(r"\[\[joints\.housing\]\].*\n(?:(?:from|to|radius) = .*\n)+")


def stick_robot(name: str) -> RobotModel:
    """The shipped robot ``name`` without its rows' housings."""
    table = load_robot(name).table
    rows = tuple(replace(row, housings=()) for row in table.rows)
    return robot_from_table(replace(table, rows=rows))


def stick_table_file(name: str, folder: Path) -> Path:
    """The shipped table file of ``name`` without its housings, written in ``folder``."""
    text = get_robot(name).table_path.read_text(encoding="utf-8")
    stripped = _HOUSING.sub("", text)
    assert "housing" not in stripped and stripped != text, f"{name=} has no housings to drop"
    path = folder / f"{name}.toml"
    path.write_text(stripped, encoding="utf-8")
    return path

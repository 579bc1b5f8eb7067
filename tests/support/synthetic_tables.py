"""The synthetic 7R table of the audit tests: its rows (cm, deg) and its table file text."""

from __future__ import annotations

#: (a [cm], alpha [deg], d [cm], theta [deg]) per row.
ROWS = (
    (5.0, -90.0, 30.0, 0.0),
    (25.0, 0.0, 4.0, -90.0),
    (3.0, 90.0, 0.0, 90.0),
    (0.0, -90.0, 22.0, 0.0),
    (0.0, 90.0, 0.0, 30.0),
    (2.0, -90.0, 0.0, 0.0),
    (0.0, 0.0, 8.0, 0.0),
)
TOOL = "[tool]\nxyz = [1.0, 2.0, 6.0]\nrpy = [0.0, 0.0, 0.0]\n"


def table_toml(rows=ROWS, convention="standard", scale=1.0, tool=TOOL, name="syn7") -> str:
    """A table file text: ``scale`` multiplies the lengths (their unit stays cm)."""
    text = f'name = "{name}"\nconvention = "{convention}"\nlength_unit = "cm"\nangle_unit = "deg"\n'
    for a, alpha, d, theta in rows:
        text += (
            f'\n[[joints]]\ntype = "revolute"\na = {a * scale}\nalpha = {alpha}\n'
            f"d = {d * scale}\ntheta = {theta}\nlimits = [-170.0, 170.0]\n"
        )
    if tool:
        xyz = ", ".join(str(v * scale) for v in (1.0, 2.0, 6.0))
        text += f"\n[tool]\nxyz = [{xyz}]\nrpy = [0.0, 0.0, 0.0]\n"
    return text

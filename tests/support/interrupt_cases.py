"""The inputs of the interruption tests: an eight-joint arm (numeric solver only) and a pose file
of many targets for it.
"""

from __future__ import annotations

#: An eight-joint arm (no closed form: every line goes to the numeric solver, about 5000 lines/s).
SNAKE8_TOML = """
name = "snake8"
description = "8R test arm for the stream's Ctrl-C"
source = "tests/commands/test_interrupts.py: invented"
convention = "standard"
length_unit = "m"
angle_unit = "deg"
""" + "".join(
    f'\n[[joints]]\nname = "j{k}"\ntype = "revolute"\na = {a}\nalpha = {alpha}\nd = {d}\n'
    "theta = 0.0\nlimits = [-170.0, 170.0]\n"
    for k, (a, alpha, d) in enumerate(
        [(0.0, 90, 0.3), (0.25, 0, 0), (0.0, 90, 0), (0.0, -90, 0.25)]
        + [(0.0, 90, 0), (0.0, -90, 0.2), (0.1, 90, 0), (0.0, 0, 0.1)],
        start=1,
    )
)


def _pose_file(robot_argument: str, path, count: int) -> None:
    """``count`` lines {"target", "rpy"}: 2000 poses of random q within the limits, repeated."""
    import json

    import numpy as np
    import pinocchio as pin

    from kin import Configuration, load_robot

    robot = load_robot(robot_argument)
    configuration = Configuration(robot)
    q_all = np.random.default_rng(3).uniform(robot.lower, robot.upper, (2000, robot.nq))
    lines = []
    for q in q_all:
        pose = configuration.fk(q)
        rpy = pin.rpy.matrixToRpy(pose.rotation).tolist()
        lines.append(json.dumps({"target": pose.translation.tolist(), "rpy": rpy}) + "\n")
    path.write_text("".join(lines[k % len(lines)] for k in range(count)))

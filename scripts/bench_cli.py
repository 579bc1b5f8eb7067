"""Wall times of the ``kin`` command and the throughput of ``kin ik --stdin``; print a table.

Each command runs in a fresh interpreter, ``--runs`` times; the table gives the median wall time
[s]. The ``--stdin`` rows feed targets (tool poses of random joint vectors within the limits) to
one ``kin ik --stdin`` process and count answers per second after the first answer (start-up
paid once). The last rows split a ``kin ik --robot humanoid7`` start-up into its parts.

Figures to reach: ``kin fk`` under 0.3 s, ``kin ik --robot humanoid7`` under 0.5 s, the same two
commands on a table file (humanoid7's table copied to a temporary folder, as a user's own arm)
within 1.2x of the shipped robot's time, ``--stdin`` at least 2,000 humanoid7 full poses/s and
10,000 closed-form targets/s.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from dh2urdf import get_robot
from kin import Configuration, load_robot
from kin.cli import ArgumentParser, positive_int

Q7 = [0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2]
#: A table file may take this much longer than the same shipped robot.
TABLE_FILE_FACTOR = 1.2

_BREAKDOWN = """
import time
t0 = time.perf_counter()
import kin.ik
t1 = time.perf_counter()
from kin import load_robot
robot = load_robot("humanoid7")
t2 = time.perf_counter()
solver = kin.ik.get_solver(robot)
t3 = time.perf_counter()
getattr(solver, "table", None)
t4 = time.perf_counter()
solver.solve(kin.ik.PositionTarget([0.4, 0.2, -0.1]))
t5 = time.perf_counter()
print(t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4)
"""


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_cli.py", description=__doc__)
    parser.add_argument(
        "--runs", type=positive_int, default=5, help="runs per figure, median kept (default 5)"
    )
    parser.add_argument(
        "--targets",
        type=positive_int,
        default=2000,
        help="humanoid7 targets per --stdin run (default 2000; 10x for the closed form)",
    )
    parser.add_argument(
        "--closed-form-robot", default="pickplace3", help="closed-form arm (default pickplace3)"
    )
    return parser


def kin_command() -> list[str]:
    """The ``kin`` console script next to this interpreter, else ``python -m kin``."""
    script = Path(sys.executable).with_name("kin")
    return [str(script)] if script.exists() else [sys.executable, "-m", "kin"]


def median_wall(command: list[str], runs: int) -> float:
    """Median wall time [s] of ``command`` over ``runs`` runs (it must exit 0)."""
    walls = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True)
        walls.append(time.perf_counter() - start)
    return statistics.median(walls)


def target_lines(name: str, count: int, full: bool, seed: int = 0) -> list[str]:
    """JSON target lines: tool poses (or positions) of random q within the limits."""
    robot = load_robot(name)
    configuration = Configuration(robot)
    rng = np.random.default_rng(seed)
    lines = []
    for q in rng.uniform(robot.lower, robot.upper, size=(count, robot.nq)):
        pose = configuration.fk(q)
        record = {"target": pose.translation.tolist()}
        if full:
            record["rpy"] = pin.rpy.matrixToRpy(pose.rotation).tolist()
        lines.append(json.dumps(record) + "\n")
    return lines


def throughput(name: str, lines: list[str]) -> tuple[float, int]:
    """Answers per second of one ``kin ik --stdin`` process after its first answer, successes."""
    process = subprocess.Popen(
        [*kin_command(), "ik", "--robot", name, "--stdin"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
    )
    assert process.stdin is not None and process.stdout is not None
    process.stdin.write(lines[0].encode())
    process.stdin.flush()
    first = process.stdout.readline()
    start = time.perf_counter()
    rest, _ = process.communicate("".join(lines[1:]).encode())
    elapsed = time.perf_counter() - start
    answers = [first, *rest.splitlines()]
    successes = sum(bool(json.loads(answer).get("success")) for answer in answers)
    return (len(lines) - 1) / elapsed, successes


def main(argv: list[str] | None = None) -> int:
    """Print the table; exit 0."""
    args = get_argument_parser().parse_args(argv)
    kin = kin_command()
    robot = load_robot("humanoid7")
    pose = Configuration(robot).fk(np.array(Q7))
    rpy = pin.rpy.matrixToRpy(pose.rotation).tolist()
    position = pose.translation.tolist()
    q_text = [f"{v:g}" for v in Q7]
    fk_args = ["fk", "--q", *q_text]
    ik_args = ["ik", "--target", *map(repr, position), "--rpy", *map(repr, rpy)]
    print(f"wall time, median of {args.runs} runs ({' '.join(kin)})")
    print(f"{'command':<50} {'median':>12}  goal")
    with tempfile.TemporaryDirectory() as folder:
        table_file = Path(folder) / "my_arm.toml"  # a user's own table: not a shipped name
        table_file.write_bytes(get_robot("humanoid7").table_path.read_bytes())
        fk_label = "kin fk --robot humanoid7 --q ..."
        ik_label = "kin ik --robot humanoid7 --target ... --rpy ..."
        # (label, command, goal): a goal in [s], or the label of the row to stay within 1.2x of.
        rows: list[tuple[str, list[str], float | str | None]] = [
            ('python -c "import pinocchio"', [sys.executable, "-c", "import pinocchio"], None),
            (fk_label, [*kin, *fk_args, "--robot", "humanoid7"], 0.3),
            (
                "kin fk --robot my_arm.toml --q ...",
                [*kin, *fk_args, "--robot", str(table_file)],
                fk_label,
            ),
            (ik_label, [*kin, *ik_args, "--robot", "humanoid7"], 0.5),
            (
                "kin ik --robot my_arm.toml --target ... --rpy ...",
                [*kin, *ik_args, "--robot", str(table_file)],
                ik_label,
            ),
            ("kin robots", [*kin, "robots"], None),
        ]
        walls: dict[str, float] = {}
        for label, command, goal in rows:
            wall = walls[label] = median_wall(command, args.runs)
            if isinstance(goal, str):
                goal = round(TABLE_FILE_FACTOR * walls[goal], 3)
            verdict = "" if goal is None else f"< {goal} s: {'met' if wall < goal else 'MISSED'}"
            print(f"{label:<50} {wall:>10.3f} s  {verdict}")
    cases = [
        ("humanoid7", "full pose", target_lines("humanoid7", args.targets, True), 2000),
        (
            args.closed_form_robot,
            "position",
            target_lines(args.closed_form_robot, 10 * args.targets, False),
            10000,
        ),
    ]
    for name, kind, lines, goal in cases:
        rates, successes = zip(*(throughput(name, lines) for _ in range(args.runs)))
        rate = statistics.median(rates)
        label = f"kin ik --stdin {name} {kind} ({len(lines)} targets)"
        verdict = f">= {goal}/s: {'met' if rate >= goal else 'MISSED'}"
        print(f"{label:<50} {rate:>8.0f} /s  {verdict}; success {min(successes)}/{len(lines)}")
    done = subprocess.run(
        [sys.executable, "-c", _BREAKDOWN], check=True, capture_output=True, text=True
    )
    parts = [float(v) for v in done.stdout.split()]
    names = ("import kin.ik", "load_robot humanoid7", "get_solver", "seed table", "first solve")
    print("kin ik --robot humanoid7 start-up, in one fresh interpreter [s]:")
    print("  " + ", ".join(f"{n} {v:.3f}" for n, v in zip(names, parts)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

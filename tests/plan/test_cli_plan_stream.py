"""``kin plan --stdin``: one answer line per request line, in order, errors as lines, stops.

Each answer is checked against ``kin plan --json`` run alone with the same options (the same
seed and work bound give the same path), and its ends against the request converted here.
"""

from __future__ import annotations

import io
import json
import math
import os
import signal
import subprocess

import numpy as np
import pytest
from support.cli_helper import assert_one_line_error, call, kin_command
from support.plan_support import write_ball

from kin.commands import plan as plan_command

#: Lines that plan (in degrees) and lines that fail, with what each answer must say.
LINES = [
    ({"start": [-90, 0], "goal": [90, 0], "deg": True, "seed": 4}, "ok"),
    ({"start": [-1.5, 0.2], "target": [0, 0.5, 0]}, "ok"),
    ({"start": [0, 0], "goal": [1, 0]}, "start_in_collision"),
    ("not json", "not JSON"),
    ("", "blank line"),
    ({"start": [-1.5, 0], "goal": [1, 0], "planner": "RRTx"}, "unknown planner 'RRTx'"),
    ({"start": [-1.5, 0, 3], "goal": [1, 0]}, '"start" needs 2 values'),
    ('{"start": [NaN, 0], "goal": [1, 0]}', '"start" values must be finite'),
    ({"start": [-1.5, 0], "goal": [9, 0]}, "\"goal\": joint 'joint1' value 9 rad is outside"),
    ({"start": [-1.5, 0], "goal": [1, 0], "speed": 3}, "unknown key(s) ['speed']"),
    ({"start": [-1.5, 0], "goal": [1, 0], "time_limit": 0}, '"time_limit" must be a positive'),
    ({"start": [-1.5, 0], "goal": [1, 0], "rpy": [0, 0, 0]}, 'go with "target"'),
    ({"start": [-90, 0], "goal": [90, 0], "deg": True, "max_checks": 3}, "not_found"),
    ({"start": [-90, 0], "goal": [90, 0], "deg": True, "seed": 9, "time": True}, "ok"),
]


@pytest.fixture
def ball(tmp_path):
    return write_ball(tmp_path)


def _text(line: dict | str) -> str:
    return line if isinstance(line, str) else json.dumps(line)


def _stream(monkeypatch, capsys, argv: list[str], lines: list[str], code: int) -> list[dict]:
    """The answers of ``kin plan --stdin`` in this process (stderr asserted empty)."""
    monkeypatch.setattr("sys.stdin", io.StringIO("".join(line + "\n" for line in lines)))
    assert call(plan_command.main, [*argv, "--stdin"]) == code
    captured = capsys.readouterr()
    assert captured.err == ""
    return [json.loads(line) for line in captured.out.splitlines()]


def _alone(capsys, request: dict, ball: str) -> dict:
    """``kin plan --json`` with a line's request as options."""
    argv = ["--robot", "planar2", "--scene", ball, "--json", "--start"]
    argv += [str(v) for v in request["start"]]
    argv += ["--goal", *map(str, request["goal"])] if "goal" in request else []
    argv += ["--target", *map(str, request["target"])] if "target" in request else []
    for key in ("seed", "max_checks"):
        if key in request:
            argv += [f"--{key.replace('_', '-')}", str(request[key])]
    argv += ["--deg"] * request.get("deg", False) + ["--time"] * request.get("time", False)
    call(plan_command.main, argv)
    return json.loads(capsys.readouterr().out)


def test_every_line_gets_its_answer_in_order(monkeypatch, capsys, ball):
    """One answer per line, numbered; errors and a blank line as lines; exit 1 (some failed).
    Each plan equals `kin plan --json` alone, and starts and ends where the line says."""
    lines = [_text(line) for line, _ in LINES]
    answers = _stream(monkeypatch, capsys, ["--robot", "planar2", "--scene", ball], lines, 1)
    assert [a["line"] for a in answers] == list(range(1, len(LINES) + 1))
    for (request, expected), answer in zip(LINES, answers):
        if "status" in answer:
            assert answer["status"] == expected, answer
        else:
            assert expected in answer.get("error", answer.get("skipped")), answer
            assert set(answer) in ({"line", "error"}, {"line", "skipped"})
            continue
        alone = _alone(capsys, request, ball)
        for key in ("status", "message", "path", "checks", "goals", "length", "t", "qd"):
            assert answer.get(key) == alone.get(key), key
        if answer["status"] == "ok":
            scale = math.pi / 180 if request.get("deg") else 1.0
            np.testing.assert_allclose(answer["path"][0], np.array(request["start"]) * scale)
            if "goal" in request:
                np.testing.assert_allclose(answer["path"][-1], np.array(request["goal"]) * scale)
            else:  # planar2's tool at (0, 0.5): the arm straight up
                np.testing.assert_allclose(answer["path"][-1], [math.pi / 2, 0.0], atol=1e-6)
    assert answers[-1]["t"][0] == 0.0 and len(answers[-1]["qd"]) == len(answers[-1]["path"])


def test_the_command_line_gives_the_defaults(monkeypatch, capsys, ball):
    """--start, --deg, --seed, --planner, --time from the command line; a line overrides them."""
    argv = ["--robot", "planar2", "--scene", ball, "--start", "-90", "0", "--deg", "--seed", "4"]
    argv += ["--planner", "RRT", "--time"]
    lines = [json.dumps({"goal": [90, 0]}), json.dumps({"goal": [1.5, 0], "deg": False})]
    first, second = _stream(monkeypatch, capsys, argv, lines, 0)
    assert first["planner"] == second["planner"] == "RRT" and first["seed"] == 4
    assert "t" in first and "t" in second
    np.testing.assert_allclose(first["path"][-1], [math.pi / 2, 0.0])
    np.testing.assert_allclose(second["path"][-1], [1.5, 0.0])
    np.testing.assert_allclose(second["path"][0], [-math.pi / 2, 0.0])  # --start in degrees


def test_degrees_without_deg_are_named_in_the_error(monkeypatch, capsys):
    """90 read as radians is outside planar2's limits: the error says so and suggests deg."""
    lines = [json.dumps({"start": [0, 0], "goal": [0, 90]})]
    (answer,) = _stream(monkeypatch, capsys, ["--robot", "planar2"], lines, 1)
    assert "joint2" in answer["error"] and 'degrees? then add "deg": true' in answer["error"]


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--goal", "1", "0"], "drop --goal"),
        (["--target", "0", "0.5", "0"], "drop --target"),
        (["-o", "plan.json"], "drop -o"),
        (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "not both"),
        (["--workers", "0"], "--workers"),
        (["--scene", "missing.toml"], "missing.toml"),
    ],
)
def test_bad_options_are_one_line_exit_2(monkeypatch, capsys, ball, extra, needle):
    monkeypatch.setattr("sys.stdin", io.StringIO('{"start": [0, 0], "goal": [1, 0]}\n'))
    code = call(plan_command.main, ["--robot", "planar2", "--stdin", *extra])
    captured = capsys.readouterr()
    assert_one_line_error(code, captured.err, needle)
    assert captured.out == ""


def test_workers_need_stdin(capsys):
    code = call(plan_command.main, ["--robot", "planar2", "--start", "0", "0", "--workers", "2"])
    assert_one_line_error(code, capsys.readouterr().err, "give --stdin")


def test_each_answer_comes_before_the_next_line_is_written(ball):
    """A client that writes a line and waits gets its answer: three rounds, one line each."""
    process = subprocess.Popen(
        [*kin_command(), "plan", "--robot", "planar2", "--scene", ball, "--stdin", "--deg"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
    )
    answers = []
    for goal in ([90, 0], [120, 10], [45, -20]):
        request = {"start": [-90, 0], "goal": goal}
        process.stdin.write((json.dumps(request) + "\n").encode())
        process.stdin.flush()
        answers.append(json.loads(process.stdout.readline()))  # blocks if not flushed
    process.stdin.close()
    assert process.wait(timeout=120) == 0 and process.stdout.read() == b""
    assert [a["line"] for a in answers] == [1, 2, 3]
    assert all(a["status"] == "ok" for a in answers)


def _requests(count: int) -> str:
    """``count`` planar2 swings across the ball, each seeded by its number (deg)."""
    rng = np.random.default_rng(1)
    lines = []
    for seed in range(count):
        start = [rng.uniform(-170, -20), rng.uniform(-30, 30)]
        goal = [rng.uniform(20, 170), rng.uniform(-30, 30)]
        lines.append(json.dumps({"start": start, "goal": goal, "deg": True, "seed": seed}))
    return "".join(line + "\n" for line in lines)


@pytest.mark.parametrize(
    ("signum", "code", "said"),
    [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated")],
)
def test_a_stop_keeps_the_answers_written(tmp_path, ball, signum, code, said):
    """Ctrl-C or SIGTERM while planning a file: the answers written are whole lines 1..k, in
    order, at least one; exit 130 / 143 and one line on stderr."""
    source = tmp_path / "in.jsonl"
    source.write_text(_requests(5000), encoding="utf-8")
    with source.open("rb") as stdin:
        process = subprocess.Popen(
            [*kin_command(), "plan", "--robot", "planar2", "--scene", ball, "--stdin"],
            stdin=stdin,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        try:
            first = process.stdout.readline()  # planning now
            process.send_signal(signum)
            rest = process.stdout.read()  # not communicate(): it skips what readline buffered
            err = process.stderr.read()
            process.wait(timeout=120)
        finally:
            process.kill()
    assert process.returncode == code, err
    assert err.decode().splitlines() == [f"kin plan: {said}"]
    text = (first + rest).decode()
    assert text.endswith("\n")
    numbers = [json.loads(line)["line"] for line in text.splitlines()]
    assert numbers == list(range(1, len(numbers) + 1)) and 0 < len(numbers) < 5000


def test_progress_bar_on_a_terminal(monkeypatch, capsys, ball):
    """stderr a terminal, stdin not: the bar counts the plans; the answers are unchanged."""

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    terminal = Terminal()
    monkeypatch.setattr("sys.stderr", terminal)
    monkeypatch.setattr("sys.stdin", io.StringIO(_requests(3)))
    argv = ["--robot", "planar2", "--scene", ball, "--stdin"]
    assert call(plan_command.main, argv) == 0
    assert len(capsys.readouterr().out.splitlines()) == 3
    drawn = terminal.getvalue()
    assert "kin plan: [" in drawn and "3/3 plans 100%" in drawn and drawn.endswith("\n")


@pytest.mark.slow
def test_on_a_local_dask_cluster_the_answers_are_the_same_and_in_order(tmp_path, ball):
    """--workers 2: the same answers as in this process (paths, checks), in input order, with a
    bad line among them; each worker plans with its own OMPL seed per plan."""
    text = _requests(40).splitlines()
    text.insert(7, "{bad")
    source = tmp_path / "in.jsonl"
    source.write_text("\n".join(text) + "\n", encoding="utf-8")
    command = [*kin_command(), "plan", "--robot", "planar2", "--scene", ball, "--stdin"]
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    runs = []
    for extra in ([], ["--workers", "2"]):
        with source.open("rb") as stdin:
            done = subprocess.run(
                command + extra, stdin=stdin, capture_output=True, timeout=600, env=env
            )
        assert done.returncode == 1, done.stderr  # the bad line
        runs.append([json.loads(line) for line in done.stdout.decode().splitlines()])
    here, dask = runs
    assert [a["line"] for a in dask] == list(range(1, 42))
    assert "error" in dask[7] and dask[7] == here[7]
    for one, other in zip(here, dask):
        for key in ("status", "path", "checks", "goals", "seed"):
            assert one.get(key) == other.get(key), (one["line"], key)


def _descendants(pid: int) -> list[int]:
    """The processes below ``pid`` (pgrep, level by level)."""
    found, level = [], [pid]
    while level:
        listed = [
            subprocess.run(["pgrep", "-P", str(p)], capture_output=True, text=True).stdout
            for p in level
        ]
        level = [int(child) for text in listed for child in text.split()]
        found += level
    return found


@pytest.mark.slow
def test_ctrl_c_on_a_local_dask_cluster_keeps_the_answers_and_ends_the_workers(tmp_path, ball):
    """--workers 2 and Ctrl-C after the first answer: exit 130, the answers written whole lines
    1..k in order, no worker process left running."""
    from support.process_state import _left

    source = tmp_path / "in.jsonl"
    source.write_text(_requests(2000), encoding="utf-8")
    command = [*kin_command(), "plan", "--robot", "planar2", "--scene", ball, "--stdin"]
    with source.open("rb") as stdin:
        process = subprocess.Popen(
            [*command, "--workers", "2"],
            stdin=stdin,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        workers: list[int] = []
        try:
            first = process.stdout.readline()  # the cluster is up and planning
            workers = _descendants(process.pid)
            process.send_signal(signal.SIGINT)
            rest = process.stdout.read()
            err = process.stderr.read()
            process.wait(timeout=120)
        finally:
            process.kill()
    assert process.returncode == 130, err
    assert err.decode().strip().splitlines()[-1] == "kin plan: interrupted"
    numbers = [json.loads(line)["line"] for line in (first + rest).decode().splitlines()]
    assert numbers == list(range(1, len(numbers) + 1)) and 0 < len(numbers) < 2000
    assert len(workers) >= 2 and _left(workers) == []


@pytest.mark.slow
def test_on_a_running_scheduler_the_answers_are_the_same(monkeypatch, capsys, ball):
    """--scheduler ADDRESS (two worker threads in one process, each with its own checker): the
    answers of this process, in order."""
    distributed = pytest.importorskip("distributed", reason="dask[distributed] not installed")
    lines = _requests(12).splitlines()
    argv = ["--robot", "planar2", "--scene", ball]
    here = _stream(monkeypatch, capsys, argv, lines, 0)
    cluster = distributed.LocalCluster(
        n_workers=2, processes=False, threads_per_worker=1, dashboard_address=None
    )
    with cluster:
        address = ["--scheduler", cluster.scheduler_address]
        dask = _stream(monkeypatch, capsys, [*argv, *address], lines, 0)
    assert [a["line"] for a in dask] == list(range(1, 13))
    for one, other in zip(here, dask):
        for key in ("status", "path", "checks", "goals"):
            assert one[key] == other[key], (one["line"], key)

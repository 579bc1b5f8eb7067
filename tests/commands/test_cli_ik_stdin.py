"""`kin ik --stdin`: one JSON answer per JSON target line, errors as lines, throughput."""

from __future__ import annotations

import io
import json
import subprocess

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import kin_command, run, write_rrpr4
from support.dh_reference import fk_frames, load_reference

from kin import Configuration, load_robot
from kin.commands import ik


def _pose_lines(name: str, count: int, full: bool, seed: int = 0) -> tuple[list[str], np.ndarray]:
    """JSON lines of the tool poses of ``count`` random q within the limits, and the q."""
    robot = load_robot(name)
    configuration = Configuration(robot)
    q_all = np.random.default_rng(seed).uniform(robot.lower, robot.upper, size=(count, robot.nq))
    lines = []
    for q in q_all:
        pose = configuration.fk(q)
        record = {"target": pose.translation.tolist()}
        if full:
            record["rpy"] = pin.rpy.matrixToRpy(pose.rotation).tolist()
        lines.append(json.dumps(record))
    return lines, q_all


def _stream(monkeypatch, capsys, argv: list[str], lines: list[str], code: int = 0) -> list[dict]:
    monkeypatch.setattr("sys.stdin", io.StringIO("".join(line + "\n" for line in lines)))
    assert ik.main([*argv, "--stdin"]) == code
    captured = capsys.readouterr()
    assert captured.err == ""
    return [json.loads(line) for line in captured.out.splitlines()]


def test_humanoid7_full_poses_all_on_target(monkeypatch, capsys):
    """50 full poses from FK of random q: 50 answers, each verified on the pose by Pinocchio."""
    lines, _ = _pose_lines("humanoid7", 50, full=True)
    answers = _stream(monkeypatch, capsys, ["--robot", "humanoid7"], lines)
    robot = load_robot("humanoid7")
    configuration = Configuration(robot)
    assert [a["line"] for a in answers] == list(range(1, 51))
    for answer, line in zip(answers, lines):
        request = json.loads(line)
        assert answer["success"] and answer["q_units"] == ["rad"] * 7
        reached = configuration.fk(np.array(answer["solutions"][0]["q"]))
        np.testing.assert_allclose(reached.translation, request["target"], atol=1e-5)
        target = pin.rpy.rpyToMatrix(np.array(request["rpy"]))
        np.testing.assert_allclose(reached.rotation, target, atol=1e-4)


def test_answers_equal_single_solves_in_mm_deg(monkeypatch, capsys):
    """Lines in mm / deg with a per-line seed_q answer as `kin ik` does for the same options."""
    lines = [
        json.dumps({"target": [390, 80, 300]}),
        json.dumps({"target": [390, 80, 300], "seed_q": [10, 40, -40]}),
        json.dumps({"target": [300, -50, 250], "position_only": True}),
    ]
    argv = ["--robot", "pickplace3", "--unit", "mm", "--deg"]
    answers = _stream(monkeypatch, capsys, argv, lines)
    singles = []
    for extra in ([], ["--seed-q", "10", "40", "-40"]):
        assert ik.main([*argv, "--target", "390", "80", "300", "--json", *extra]) == 0
        singles.append(json.loads(capsys.readouterr().out))
    for answer, single in zip(answers, singles):
        assert [s["q"] for s in answer["solutions"]] == [s["q"] for s in single["solutions"]]
    assert answers[0]["solutions"][0]["q"] != answers[1]["solutions"][0]["q"]  # nearest the seed
    assert answers[0]["rejected"] == [] and len(singles[0]["rejected"]) == 2  # rejected with --all
    reached = Configuration(load_robot("pickplace3")).fk(np.array(answers[2]["solutions"][0]["q"]))
    np.testing.assert_allclose(reached.translation, [0.3, -0.05, 0.25], atol=1e-9)


def test_prismatic_seed_q_in_mm(tmp_path, monkeypatch, capsys):
    """seed_q of a prismatic joint is in --unit; the answer (SI) reaches the target (NumPy DH)."""
    path = write_rrpr4(tmp_path)
    lines = [json.dumps({"target": [300, 100, 100], "seed_q": [10, 10, 50, 0]})]
    argv = ["--robot", str(path), "--unit", "mm", "--deg", "--solver", "nr"]
    (answer,) = _stream(monkeypatch, capsys, argv, lines)
    q = np.array(answer["solutions"][0]["q"])
    assert answer["q_units"] == ["rad", "rad", "m", "rad"] and abs(q[2] - 0.130) < 1e-9
    np.testing.assert_allclose(
        fk_frames(load_reference(path), q)[0, -1, :3, 3], [0.3, 0.1, 0.1], atol=1e-7
    )


@pytest.mark.parametrize(
    "line, needle",
    [
        ("not json", "not JSON"),
        ("[1, 2, 3]", "must be a JSON object"),
        ('{"tgt": [0, 0, 0]}', "unknown key(s) ['tgt']"),
        ('{"rpy": [0, 0, 0]}', 'missing "target"'),
        ('{"target": [1, 2]}', "must be 3 number(s)"),
        ('{"target": [NaN, 0, 0]}', "must be finite"),
        ('{"target": [0.3, 0, 0.3], "seed_q": [NaN, 0, 0]}', "finite"),
        ('{"target": [0.3, 0, 0.3], "seed_q": [1e400, 0, 0]}', "finite"),
        ('{"target": ["a", 0, 0]}', "must be numbers"),
        ('{"target": [0.3, 0, 0.3], "mask": [1, 1, 1, 0, 0, 1]}', "--mask needs --rpy or --quat"),
        ('{"target": [0.3, 0, 0.3], "axis": [0, 0, 1], "rpy": [0, 0, 0]}', "give one of"),
        ('{"target": [0.3, 0, 0.3], "seed_q": [0]}', "\"seed_q\" needs 3 values for 'pickplace3'"),
        ('{"target": [0.3, 0, 0.3], "seed_q": 5}', '"seed_q" must be a list'),
        ('{"target": [0.3, 0, 0.3], "position_only": 1}', '"position_only" must be true or false'),
        ('{"target": [0.3, 0, 0.3], "roll": 1}', "--roll needs --pitch"),
    ],
)
def test_bad_line_gives_an_error_line_and_the_run_goes_on(line, needle, monkeypatch, capsys):
    """A bad line answers {"line": n, "error": ...}; the next line is still solved; exit 1."""
    good = json.dumps({"target": [0.39, 0.08, 0.3]})
    lines = [good, line, "", good]
    answers = _stream(monkeypatch, capsys, ["--robot", "pickplace3"], lines, code=1)
    assert len(answers) == 4 and answers[1] == {"line": 2, "error": answers[1]["error"]}
    assert needle in answers[1]["error"]
    assert answers[2] == {"line": 3, "skipped": "blank line"}
    assert answers[0]["success"] and answers[3]["success"] and answers[3]["line"] == 4


def _answers(name: str, lines: list[str]) -> list[dict]:
    """The answers of `kin ik --stdin` in a subprocess to ``lines``, fed after the first answer."""
    data = "".join(line + "\n" for line in lines).encode()
    process = subprocess.Popen(
        [*kin_command(), "ik", "--robot", name, "--stdin"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
    )
    process.stdin.write(data[: data.index(b"\n") + 1])
    process.stdin.flush()
    first = process.stdout.readline()  # start-up and the first answer
    rest, _ = process.communicate(data[data.index(b"\n") + 1 :], timeout=300)
    assert process.returncode == 0
    return [json.loads(first)] + [json.loads(a) for a in rest.decode().splitlines()]


def test_many_lines_in_a_subprocess():
    """Thousands of lines through one process: one answer per line, each solved and on target by
    Pinocchio. The throughput is a benchmark's figure (scripts/bench_cli.py), not a test's."""
    for name, count, full in (("humanoid7", 1000, True), ("pickplace3", 4000, False)):
        lines, _ = _pose_lines(name, count, full=full)
        answers = _answers(name, lines)
        assert len(answers) == count and all(a["success"] for a in answers), name
        configuration = Configuration(load_robot(name))
        for line, answer in zip(lines[::97], answers[::97]):
            q = answer["solutions"][0]["q"]
            position = configuration.fk(np.array(q)).translation
            assert np.allclose(position, json.loads(line)["target"], atol=1e-6), name


def test_closed_pipe_ends_the_stream_quietly(tmp_path):
    """`kin ik --stdin < many | head -c 10`: exit 0, nothing on stderr."""
    lines, _ = _pose_lines("pickplace3", 3000, full=False)
    source = tmp_path / "targets.jsonl"
    source.write_text("".join(line + "\n" for line in lines))
    with source.open("rb") as stdin:
        writer = subprocess.Popen(
            [*kin_command(), "ik", "--robot", "pickplace3", "--stdin"],
            stdin=stdin,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        reader = subprocess.Popen(["head", "-c", "10"], stdin=writer.stdout, stdout=subprocess.PIPE)
        writer.stdout.close()
        head, _ = reader.communicate(timeout=60)
        err = writer.stderr.read()
        writer.stderr.close()
        assert writer.wait(timeout=60) == 0 and err == b"" and len(head) == 10


def test_no_valid_solution_keeps_the_best_attempt(monkeypatch, capsys):
    """Without a valid solution the answer keeps the rejected one (nr: Table IX case 1, cm)."""
    lines = [json.dumps({"target": [-37.457, -2.759, 18.861]})]
    argv = ["--robot", "humanoid7", "--unit", "cm", "--solver", "nr"]
    (answer,) = _stream(monkeypatch, capsys, argv, lines, code=1)
    assert not answer["success"] and answer["status"] == "outside_limits"
    assert answer["solutions"] == [] and answer["rejected"][0]["position_error_m"] < 1e-7
    assert answer["rejected"][0]["rotation_error_rad"] is None


def test_ctrl_c_while_waiting_for_input_exits_130():
    """Ctrl-C while the stream waits for a line: `kin ik: interrupted` on stderr, exit 130."""
    import signal

    process = subprocess.Popen(
        [*kin_command(), "ik", "--robot", "pickplace3", "--stdin"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    process.stdin.write(b'{"target": [0.39, 0.08, 0.3]}\n')
    process.stdin.flush()
    assert json.loads(process.stdout.readline())["success"]  # started, now waiting
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 130 and err.decode().splitlines() == ["kin ik: interrupted"]


def test_each_answer_comes_before_the_next_line_is_written():
    """A client that writes a line and waits gets its answer: three rounds, one line each."""
    process = subprocess.Popen(
        [*kin_command(), "ik", "--robot", "pickplace3", "--unit", "mm", "--stdin"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
    )
    targets = [[390, 80, 300], [300, -50, 250], [1, 2]]
    answers = []
    for target in targets:
        process.stdin.write((json.dumps({"target": target}) + "\n").encode())
        process.stdin.flush()
        answers.append(json.loads(process.stdout.readline()))  # blocks if not flushed
    process.stdin.close()
    assert process.wait(timeout=60) == 1 and process.stdout.read() == b""  # line 3 failed
    assert [a["line"] for a in answers] == [1, 2, 3]
    assert answers[0]["success"] and answers[1]["success"] and "error" in answers[2]
    reached = Configuration(load_robot("pickplace3")).fk(np.array(answers[1]["solutions"][0]["q"]))
    np.testing.assert_allclose(reached.translation, [0.3, -0.05, 0.25], atol=1e-9)


@pytest.mark.parametrize("read, chunk", [(1 << 16, 1 << 20), (1 << 12, 1 << 14), (7, 50)])
def test_line_batches_of_a_pipe_keep_every_line(tmp_path, monkeypatch, read, chunk):
    """Lines read in batches from a file descriptor (reads of ``read`` bytes, batches of up to
    ``chunk`` while more is there, lines cut across reads): all there, in order, the last one
    unended."""
    from kin.commands import ik_stream

    monkeypatch.setattr(ik_stream, "_READ", read)
    monkeypatch.setattr(ik_stream, "_CHUNK", chunk)
    path = tmp_path / "lines.txt"
    path.write_bytes(b"".join(b'{"target": [%d, 0, 0]}\n' % i for i in range(60000)) + b"tail")
    with path.open("rb") as source:
        batches = list(ik_stream.line_batches(source))
    lines = [line for batch in batches for line in batch]
    assert len(batches) > 1 and len(lines) == 60001 and lines[-1] == b"tail"
    assert [json.loads(line)["target"][0] for line in lines[:-1]] == list(range(60000))
    assert max(sum(map(len, batch)) for batch in batches) <= chunk + read  # a batch: <= chunk


def test_a_batch_ends_where_the_input_waits():
    """Through a pipe whose writer pauses: the lines written before the pause are one batch,
    yielded without waiting for more (the caller answers them first)."""
    import os
    import threading

    from kin.commands.ik_stream import line_batches

    read_end, write_end = os.pipe()
    gate = threading.Event()

    def writer() -> None:
        os.write(write_end, b"a\nb\n")
        gate.wait(10)
        os.write(write_end, b"c\n")
        os.close(write_end)

    thread = threading.Thread(target=writer)
    thread.start()
    with os.fdopen(read_end, "rb") as source:
        batches = line_batches(source)
        assert next(batches) == [b"a", b"b"]  # before c is written
        gate.set()
        assert [line for batch in batches for line in batch] == [b"c"]
    thread.join(10)


def test_an_unexpected_exception_in_one_line_is_that_lines_error(monkeypatch, capsys):
    """A solver that raises something nobody foresaw: that line's error record, the rest solved."""
    from kin.commands.ik_stream import StreamSolver
    from kin.commands.joint_units import JointUnits

    robot = load_robot("pickplace3")
    real = __import__("kin.ik", fromlist=["get_solver"]).get_solver(robot)

    def solve(target, seed):
        if target.position[0] > 0.35:
            raise ZeroDivisionError("boom")
        return real.solve(target, seed)

    units = JointUnits.of(robot.name, robot.table, "m", False)
    stream = StreamSolver(robot.name, robot.nq, units, solve, None, None, 1.0, 1.0)
    out = io.StringIO()
    lines = [json.dumps({"target": t}) for t in ([0.3, -0.05, 0.25], [0.39, 0.08, 0.3])] * 2
    assert stream.run(io.StringIO("\n".join(lines) + "\n"), out) == 1
    answers = [json.loads(line) for line in out.getvalue().splitlines()]
    assert [a["line"] for a in answers] == [1, 2, 3, 4]
    assert answers[0]["success"] and answers[2]["success"]
    assert answers[1] == answers[3] | {"line": 2}
    assert answers[1]["error"] == "internal error: ZeroDivisionError: boom"


@pytest.mark.slow
def test_batched_stream_gives_the_per_line_answers():
    """Hundreds of lines through a pipe (read in batches): plain poses and positions are answered
    together, the rest line by line; every answer is the one `kin ik` gives that line alone."""
    import numpy as np

    from kin import load_robot
    from kin.batch_fk import batch_forward_kinematics

    robot = load_robot("humanoid7")
    rng = np.random.default_rng(4)
    q = rng.uniform(robot.lower, robot.upper, size=(240, robot.nq))
    poses = batch_forward_kinematics(robot.table, q)
    lines = []
    for i, pose in enumerate(poses):
        target = pose[:3, 3].tolist()
        r = pose[:3, :3]
        rpy = [
            float(np.arctan2(r[2, 1], r[2, 2])),
            float(np.arcsin(-np.clip(r[2, 0], -1.0, 1.0))),
            float(np.arctan2(r[1, 0], r[0, 0])),
        ]
        kind = i % 8
        if kind == 0:
            lines.append(json.dumps({"target": target}))
        elif kind == 1:
            lines.append(json.dumps({"target": target, "rpy": rpy, "seed_q": q[i].tolist()}))
        elif kind == 2:
            lines.append("")
        elif kind == 3:
            lines.append(json.dumps({"target": [1e3, 0.0, 0.0], "rpy": rpy}))
        elif kind == 4:
            lines.append(json.dumps({"target": target, "position_only": True}))
        elif kind == 5:
            lines.append('{"target": [1, 2]}')
        else:
            lines.append(json.dumps({"target": target, "rpy": rpy}))
    done = run(["ik", "--robot", "humanoid7", "--stdin"], stdin="\n".join(lines) + "\n")
    answers = [json.loads(line) for line in done.stdout.splitlines()]
    assert [a["line"] for a in answers] == list(range(1, len(lines) + 1))
    for number in range(0, len(lines), 7):  # every 7th line, alone
        alone = run(["ik", "--robot", "humanoid7", "--stdin"], stdin=lines[number] + "\n")
        single = json.loads(alone.stdout)
        both = answers[number]
        assert set(single) - {"time_s"} == set(both) - {"time_s"}, number
        for key in ("success", "status", "method", "error", "skipped"):
            assert single.get(key) == both.get(key), (number, key)
        if single.get("solutions"):
            np.testing.assert_allclose(
                single["solutions"][0]["q"], both["solutions"][0]["q"], atol=1e-12
            )


def test_fragments_and_doubled_values_are_each_their_own_lines_error():
    """Lines read together are read one by one: a line holding two values, a fragment whose
    string swallows a brace, a value framed by spaces; each answers for itself, in order."""
    plain = json.dumps(
        {"target": [0.755721, -0.113688, 0.160173], "rpy": [0.652388, -0.162705, -0.237224]}
    )
    lines = [
        '{"x": "}',  # with the next: one object, if lines were joined
        '{"}',
        plain + ", " + plain,  # two values in one line
        "  " + plain + "  ",  # spaces around one value: a valid line
        plain,
    ]
    done = run(["ik", "--robot", "humanoid7", "--stdin"], stdin="\n".join(lines) + "\n")
    answers = [json.loads(line) for line in done.stdout.splitlines()]
    assert [a["line"] for a in answers] == [1, 2, 3, 4, 5]
    assert all("not JSON" in answers[k]["error"] for k in range(3)), answers[:3]
    assert answers[3]["success"] and answers[4]["success"]
    assert answers[3]["solutions"][0]["q"] == answers[4]["solutions"][0]["q"]

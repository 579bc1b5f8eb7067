"""Ctrl-C stops any long command at once, workers included: exit 130, nothing half-written."""

from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path

import pytest
from support.cli_helper import kin_command
from support.interrupt_cases import SNAKE8_TOML, _pose_file
from support.process_state import HANG_GUARD, cpu_seconds, wait_until


def _group_alive(pgid: int) -> list[str]:
    found = subprocess.run(["pgrep", "-g", str(pgid)], capture_output=True, text=True)
    return found.stdout.split()


def _children(pid: int) -> list[int]:
    found = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True)
    return [int(child) for child in found.stdout.split()]


def _holds_sigint(pid: int, field: str) -> bool:
    """Whether SIGINT is in ``field`` (``SigIgn``, ``SigCgt``, ``SigBlk``) of the process's
    /proc status (False once the process is gone)."""
    try:
        lines = Path(f"/proc/{pid}/status").read_text().splitlines()
    except OSError:
        return False
    masks = dict(line.split(":\t", 1) for line in lines if line.startswith("Sig"))
    return bool(int(masks[field], 16) >> (signal.SIGINT - 1) & 1)


def _pool_working(pid: int) -> bool:
    """Both workers forked and started: each ignores SIGINT and no longer blocks it."""
    workers = _children(pid)
    return len(workers) == 2 and all(
        _holds_sigint(worker, "SigIgn") and not _holds_sigint(worker, "SigBlk")
        for worker in workers
    )


@pytest.mark.parametrize("signals", [1, 2])
def test_ctrl_c_stops_a_workspace_run_with_two_workers(signals, tmp_path):
    """SIGINT to the process group (as a terminal's Ctrl-C), once or twice 0.3 s apart: the
    parent and both workers are gone, exit 130, nothing written (a hang fails the test at
    :data:`HANG_GUARD`; how fast it stops is a figure for a benchmark, not an assertion)."""
    out = tmp_path / "ws.png"
    process = subprocess.Popen(
        [*kin_command(), "workspace", "--robot", "humanoid7", "--n", "100000000"]
        + ["--workers", "2", "-o", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    try:
        wait_until(lambda: _pool_working(process.pid), process, "the pool working")
        os.killpg(process.pid, signal.SIGINT)
        if signals == 2:
            time.sleep(0.3)
            os.killpg(process.pid, signal.SIGINT)
        _, err = process.communicate(timeout=HANG_GUARD)
        assert process.returncode == 130, err
        assert err.decode().strip().splitlines()[-1] == "kin workspace: interrupted"
        time.sleep(0.2)
        assert _group_alive(process.pid) == []
        assert list(tmp_path.iterdir()) == []  # no figure, no temporary file
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)


@pytest.mark.parametrize("attempt", range(3))
def test_ctrl_c_while_the_pool_starts_stops_the_run(attempt):
    """SIGINT to the process group the moment the first worker process exists (the pool still
    starting: a worker may not yet ignore it): exit 130, no process left."""
    process = subprocess.Popen(
        [*kin_command(), "workspace", "--robot", "humanoid7", "--n", "100000000"]
        + ["--workers", "2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    try:
        deadline = time.monotonic() + HANG_GUARD
        while not _children(process.pid):  # polled fast: the first worker, not yet started
            assert process.poll() is None and time.monotonic() < deadline
            time.sleep(0.002)
        os.killpg(process.pid, signal.SIGINT)
        _, err = process.communicate(timeout=HANG_GUARD)
        assert process.returncode == 130, err
        assert err.decode().strip().splitlines()[-1] == "kin workspace: interrupted"
        assert b"Traceback" not in err  # no worker saw the Ctrl-C before ignoring it
        time.sleep(0.2)
        assert _group_alive(process.pid) == []
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)


def test_kill_int_stops_a_run_started_with_sigint_ignored():
    """A job started with SIGINT ignored (`cmd &` in a script, `timeout -s INT`) still stops on
    SIGINT: exit 130."""
    process = subprocess.Popen(
        [*kin_command(), "workspace", "--robot", "humanoid7", "--n", "200000000"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN),
    )
    try:  # the command puts SIGINT's handler back (before, an ignored SIGINT would be lost)
        wait_until(lambda: _holds_sigint(process.pid, "SigCgt"), process, "catching SIGINT")
        then = cpu_seconds(process.pid)  # then computes a while: inside the command's guard
        wait_until(lambda: cpu_seconds(process.pid) > then + 0.2, process, "computing")
        process.send_signal(signal.SIGINT)
        _, err = process.communicate(timeout=HANG_GUARD)
        assert process.returncode == 130, err
    finally:
        if process.poll() is None:
            process.kill()


def test_a_sigint_while_held_waits_for_the_release():
    """The stream's gate: between hold and release a first SIGINT is only noted and release
    raises it; a second one raises at once; outside, one raises at once; the handler restored."""
    from kin.commands.interrupt_gate import interrupt_gate

    with interrupt_gate() as gate:
        assert gate.installed
        gate.hold()
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(0.05)  # the handler runs here (and notes it)
        with pytest.raises(KeyboardInterrupt):
            gate.release()
        gate.release()  # nothing noted any more
        gate.hold()
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)
        gate.release()  # the second raised: nothing left to raise
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def _answers(text: str) -> list[dict]:
    """The answers of a stream's output, without their times (the rest is deterministic)."""
    import json

    answers = [json.loads(line) for line in text.splitlines()]
    for answer in answers:
        answer.pop("time_s", None)
    return answers


@pytest.mark.slow  # CI runs it; the default run stays under 5 minutes
@pytest.mark.parametrize(
    ("case", "options", "count", "after"),
    [
        ("humanoid7", [], 150_000, 0.5),  # the batch stage, answers encoded in C
        ("humanoid7", ["--all"], 30_000, 1.0),  # line by line, answers as dicts
        ("snake8", [], 20_000, 1.0),  # the numeric solver, line by line, ~1 s per read batch
    ],
)
def test_ctrl_c_on_the_stream_keeps_the_answers_solved(case, options, count, after, tmp_path):
    """SIGINT while `kin ik --stdin` answers a file: exit 130, the answers written are whole
    lines and exactly those of an uninterrupted run on the same first lines, at least one."""
    robot = case
    if case == "snake8":
        robot = str(tmp_path / "snake8.toml")
        (tmp_path / "snake8.toml").write_text(SNAKE8_TOML)
    source = tmp_path / "in.jsonl"
    _pose_file(robot, source, count)
    command = [*kin_command(), "ik", "--robot", robot, "--stdin", *options]
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / "cache"))
    env.pop("DH_KINEMATICS_NO_CACHE", None)
    first = tmp_path / "first.jsonl"
    first.write_text(source.read_text().split("\n", 1)[0] + "\n")
    # One line first: the seed table cached for the run below.
    subprocess.run(command, stdin=first.open("rb"), capture_output=True, env=env, check=True)
    out = tmp_path / "out.jsonl"
    with source.open("rb") as stdin, out.open("wb") as stdout:
        process = subprocess.Popen(
            command, stdin=stdin, stdout=stdout, stderr=subprocess.PIPE, env=env
        )
        try:
            # Answering (its first answers written), then ``after`` [s] more: in a read batch.
            wait_until(lambda: out.stat().st_size > 0, process, "answering")
            time.sleep(after)
            process.send_signal(signal.SIGINT)
            _, err = process.communicate(timeout=60)
        finally:
            if process.poll() is None:
                process.kill()
    assert process.returncode == 130, err
    assert err.decode().strip().splitlines()[-1] == "kin ik: interrupted"
    text = out.read_text()
    written = text.count("\n")
    assert 0 < written < count, f"{case=} {written=}: SIGINT came too late or nothing was kept"
    assert text.endswith("\n"), f"{case=}: the last line is cut: {text[-80:]!r}"
    head = tmp_path / "head.jsonl"
    head.write_text("".join(source.read_text().splitlines(keepends=True)[:written]))
    full = subprocess.run(command, stdin=head.open("rb"), capture_output=True, env=env)
    assert full.returncode in (0, 1), full.stderr
    expected = _answers(full.stdout.decode())
    got = _answers(text)
    assert len(got) == len(expected) == written
    for number, (answer, reference) in enumerate(zip(got, expected), start=1):
        assert answer == reference, f"{case=} line {number}"

"""SIGTERM stops every command as Ctrl-C does (issue 42): what is done is kept, workers are
ended, no process is left; ``prog: terminated`` and exit 143 (128 + SIGTERM).

The signal goes to the command's process alone (``kill PID``, a supervisor), not to its group
as a terminal's Ctrl-C does: the workers hear nothing but what their parent does. Timeouts only
guard against a hang (:data:`HANG_GUARD`); no test asserts how fast a stop is.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from support.cli_helper import kin_command
from support.interrupt_cases import SNAKE8_TOML, _pose_file
from support.process_state import HANG_GUARD, _left

ROOT = Path(__file__).resolve().parents[2]


def _children(pid: int, deadline: float = 60.0) -> list[int]:
    """The child processes of ``pid`` once there are two (the pool's workers started)."""
    end = time.monotonic() + deadline
    while time.monotonic() < end:
        found = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True)
        pids = [int(p) for p in found.stdout.split()]
        if len(pids) >= 2:
            return pids
        time.sleep(0.05)
    raise AssertionError(f"process {pid} started no two workers in {deadline} s")


def _kill_all(pids: list[int]) -> None:
    for pid in pids:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="reads /proc; SIGTERM handling is POSIX"
)


def test_sigterm_ends_a_workspace_run_and_both_workers(tmp_path):
    """`kin workspace --workers 2 -o ws.png | cat` and SIGTERM to the command: exit 143, one
    line, both workers gone, the pipe closed (the reader gets its end of file), no file left.
    Before: the workers were orphaned, each waiting on a pipe it held both ends of."""
    process = subprocess.Popen(
        [*kin_command(), "workspace", "--robot", "humanoid7", "--n", "100000000"]
        + ["--workers", "2", "--quiet", "-o", str(tmp_path / "ws.png")],
        stdout=subprocess.PIPE,  # as `| cat`: read to its end of file below
        stderr=subprocess.PIPE,
    )
    workers: list[int] = []
    try:
        workers = _children(process.pid)
        time.sleep(1.0)  # the workers at work on their chunks
        process.send_signal(signal.SIGTERM)
        out, err = process.communicate(timeout=HANG_GUARD)
        assert process.returncode == 143, err
        assert err.decode().splitlines() == ["kin workspace: terminated"], err
        assert out == b""
        assert _left(workers) == [], "workers left running"
        assert list(tmp_path.iterdir()) == []
    finally:
        process.kill()
        _kill_all(workers)


POOL_SCRIPT = """
import os, sys, threading, time
from kin.workspace.pool import run_unordered

def work(task):
    time.sleep(0.2)
    return os.getpid()

def main():
    for pid in run_unordered(work, iter(range(10**6)), workers=2):
        print(pid, flush=True)

if sys.argv[1] == "main":
    main()
else:
    thread = threading.Thread(target=main)
    thread.start()
    thread.join()
"""


@pytest.mark.parametrize("thread", ["main", "other"])
def test_the_pool_s_workers_end_when_their_parent_is_killed(thread, tmp_path):
    """A pool's parent killed outright (SIGKILL: no handler runs): its workers end too, whether
    the pool runs in the main thread (the kernel's parent-death signal) or another (the end of
    file on each worker's pipe, which no worker holds open itself any more)."""
    script = tmp_path / "pool.py"
    script.write_text(POOL_SCRIPT)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    process = subprocess.Popen(
        [sys.executable, str(script), thread], stdout=subprocess.PIPE, env=env
    )
    workers: list[int] = []
    try:
        assert process.stdout is not None
        while len(set(workers)) < 2:  # results from both workers: they are at work
            line = process.stdout.readline()
            assert line, "the pool ended early"
            workers.append(int(line))
        workers = sorted(set(workers))
        process.kill()
        process.wait(timeout=HANG_GUARD)
        assert _left(workers) == [], f"{thread=}: workers outlived their parent"
    finally:
        process.kill()
        _kill_all(workers)


def test_sigterm_on_the_stream_keeps_the_answers_solved(tmp_path):
    """SIGTERM while `kin ik --stdin` answers a file (the numeric solver, line by line): exit
    143, the answers solved so far written as whole lines, in order, at least one. Before: the
    process died at once and the answers of the batch being solved were lost."""
    robot = tmp_path / "snake8.toml"
    robot.write_text(SNAKE8_TOML)
    source = tmp_path / "in.jsonl"
    count = 20_000
    _pose_file(str(robot), source, count)
    command = [*kin_command(), "ik", "--robot", str(robot), "--stdin"]
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / "cache"))
    env.pop("DH_KINEMATICS_NO_CACHE", None)
    first = tmp_path / "first.jsonl"
    first.write_text(source.read_text().split("\n", 1)[0] + "\n")
    begin = time.monotonic()  # start-up and one line; the seed table cached for the run below
    subprocess.run(command, stdin=first.open("rb"), capture_output=True, env=env, check=True)
    startup = time.monotonic() - begin
    out = tmp_path / "out.jsonl"
    with source.open("rb") as stdin, out.open("wb") as stdout:
        process = subprocess.Popen(
            command, stdin=stdin, stdout=stdout, stderr=subprocess.PIPE, env=env
        )
        try:
            time.sleep(startup + 1.0)  # answering, in the middle of a read batch
            process.send_signal(signal.SIGTERM)
            _, err = process.communicate(timeout=HANG_GUARD)
        finally:
            process.kill()
    assert process.returncode == 143, err
    assert err.decode().strip().splitlines()[-1] == "kin ik: terminated"
    text = out.read_text()
    written = text.count("\n")
    assert 0 < written < count, f"{written=}: SIGTERM came too late or nothing was kept"
    assert text.endswith("\n"), f"the last line is cut: {text[-80:]!r}"
    numbers = [json.loads(line)["line"] for line in text.splitlines()]
    assert numbers == list(range(1, written + 1))


GUARDED_SCRIPT = """
import os, signal, sys, time
from dh2urdf.command_line import run_guarded

def body():
    print("done before", flush=True)
    os.kill(os.getpid(), signal.SIGTERM)
    time.sleep(30)
    return 0

code = run_guarded("demo", body)
print("after", signal.getsignal(signal.SIGTERM) == signal.SIG_DFL, flush=True)
sys.exit(code)
"""


def test_run_guarded_stops_on_sigterm_like_ctrl_c(tmp_path):
    """Any command's body: SIGTERM raises as Ctrl-C does, one line `demo: terminated`, exit
    143; SIGTERM's default is back after the command (the caller's process as it was)."""
    script = tmp_path / "guarded.py"
    script.write_text(GUARDED_SCRIPT)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=60
    )
    assert done.returncode == 143, done.stderr
    assert done.stderr == "demo: terminated\n"
    assert done.stdout == "done before\nafter True\n"


def test_a_sigterm_while_the_gate_holds_waits_for_the_release():
    """The stream's gate holds a SIGTERM as it holds a SIGINT: noted, raised by release, and
    the stop is a termination (exit 143); the command's handler is back after."""
    from dh2urdf.stop_signals import listen_to_stops, stop_on_sigterm, terminated
    from kin.commands.interrupt_gate import interrupt_gate

    restore = listen_to_stops()
    try:
        assert signal.getsignal(signal.SIGTERM) is stop_on_sigterm
        with interrupt_gate() as gate:
            gate.hold()
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.05)  # the handler runs here (and notes it)
            assert terminated()
            with pytest.raises(KeyboardInterrupt):
                gate.release()
        assert signal.getsignal(signal.SIGTERM) is stop_on_sigterm
    finally:
        restore()
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL


@pytest.mark.slow  # Dask's cluster takes seconds to start, and its close waits for the chunks
def test_sigterm_ends_a_reach_map_on_a_local_cluster(tmp_path):
    """`kin reach --scheduler local-cluster:2` and SIGTERM to the command: exit 143, one line,
    no process of its cluster left, no map written."""
    pytest.importorskip("distributed")
    process = subprocess.Popen(
        [*kin_command(), "reach", "--robot", "ur5", "--voxel", "0.02", "--orientations", "256"]
        + ["--scheduler", "local-cluster:2", "--quiet", "-o", str(tmp_path / "m.npz")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    workers: list[int] = []
    try:
        workers = _children(process.pid)
        time.sleep(5.0)  # the cluster at work
        workers = [
            int(p)
            for p in subprocess.run(
                ["pgrep", "-P", str(process.pid)], capture_output=True, text=True
            ).stdout.split()
        ]
        process.send_signal(signal.SIGTERM)
        _, err = process.communicate(timeout=3 * HANG_GUARD)
        assert process.returncode == 143, err
        assert err.decode().strip().splitlines()[-1] == "kin reach: terminated"
        assert _left(workers) == [], "cluster processes left running"
        assert not (tmp_path / "m.npz").exists()
    finally:
        process.kill()
        _kill_all(workers)

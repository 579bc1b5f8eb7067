"""Ctrl-C stops any long command at once, workers included: exit 130, nothing half-written."""

from __future__ import annotations

import os
import signal
import subprocess
import time

import pytest
from cli_helper import kin_command


def _group_alive(pgid: int) -> list[str]:
    found = subprocess.run(["pgrep", "-g", str(pgid)], capture_output=True, text=True)
    return found.stdout.split()


@pytest.mark.parametrize(("signals", "bound"), [(1, 1.0), (2, 0.5)])
def test_ctrl_c_stops_a_workspace_run_with_two_workers(signals, bound, tmp_path):
    """SIGINT to the process group (as a terminal's Ctrl-C), once or twice 0.3 s apart: the
    parent and both workers are gone within 1 s (0.5 s after the second), exit 130."""
    out = tmp_path / "ws.png"
    process = subprocess.Popen(
        [*kin_command(), "workspace", "--robot", "humanoid7", "--n", "100000000"]
        + ["--workers", "2", "-o", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    try:
        time.sleep(4.0)  # started, and the pool is working
        os.killpg(process.pid, signal.SIGINT)
        last = time.monotonic()
        if signals == 2:
            time.sleep(0.3)
            os.killpg(process.pid, signal.SIGINT)
            last = time.monotonic()
        _, err = process.communicate(timeout=30)
        stopped = time.monotonic() - last
        assert process.returncode == 130, err
        assert err.decode().strip().splitlines()[-1] == "kin workspace: interrupted"
        assert stopped < bound, f"{stopped=}"
        time.sleep(0.2)
        assert _group_alive(process.pid) == []
        assert list(tmp_path.iterdir()) == []  # no figure, no temporary file
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)


def test_kill_int_stops_a_run_started_with_sigint_ignored():
    """A job started with SIGINT ignored (`cmd &` in a script, `timeout -s INT`) still stops on
    SIGINT: exit 130 within a second."""
    process = subprocess.Popen(
        [*kin_command(), "workspace", "--robot", "humanoid7", "--n", "200000000"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN),
    )
    try:
        time.sleep(3)
        process.send_signal(signal.SIGINT)
        start = time.monotonic()
        _, err = process.communicate(timeout=30)
        assert process.returncode == 130, err
        assert time.monotonic() - start < 1.0
    finally:
        if process.poll() is None:
            process.kill()

"""What a child process is doing, read from /proc: tests send it a signal on a state, not after a
sleep, so that a slow or loaded machine only waits longer (issue 42)."""

from __future__ import annotations

import os
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

#: How long a test waits for a state, or for a stopped command to exit, before it calls the run
#: a hang [s]: a guard against a process that never gets there, far above any loaded machine.
HANG_GUARD = 60.0


def cpu_seconds(pid: int) -> float:
    """The process's CPU time so far, user and system [s] (its work, whatever the load; 0 once
    it is gone)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime, stime


def group_cpu_seconds(pgid: int) -> float:
    """The CPU time of the processes alive in process group ``pgid`` [s]."""
    found = subprocess.run(["pgrep", "-g", str(pgid)], capture_output=True, text=True)
    return sum(cpu_seconds(int(pid)) for pid in found.stdout.split())


def wait_until(ready: Callable[[], bool], process: subprocess.Popen, what: str) -> None:
    """Poll ``ready`` while ``process`` lives, for at most :data:`HANG_GUARD`."""
    deadline = time.monotonic() + HANG_GUARD
    while not ready():
        assert process.poll() is None, f"ended before {what}: exit {process.returncode}"
        assert time.monotonic() < deadline, f"not {what} after {HANG_GUARD} s"
        time.sleep(0.01)


def _running(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie (ended, not yet reaped)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError, IndexError):
        return False
    return state != "Z"


def _left(pids: list[int], guard: float = HANG_GUARD) -> list[int]:
    """Those of ``pids`` still running after up to ``guard`` seconds."""
    end = time.monotonic() + guard
    while (alive := [pid for pid in pids if _running(pid)]) and time.monotonic() < end:
        time.sleep(0.1)
    return alive

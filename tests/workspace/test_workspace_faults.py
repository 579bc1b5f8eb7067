"""Workspace runs that survive faults, in bounded memory: a killed worker process is replaced and
its chunks rerun (same statistics as an undisturbed run), a chunk that keeps killing its worker
stops the run with one error, a lost Dask scheduler is one error (exit 1 in the commands), a
huge n is made lazily, and Ctrl-C leaves no worker behind."""

from __future__ import annotations

import logging
import multiprocessing
import os
import signal
import tracemalloc

import numpy as np
import pytest

from dh2urdf import get_robot
from kin import KinError, RunFaultError
from kin.commands.workspace import main as workspace_main
from kin.workspace import WorkspaceGrid, chunk_seed, chunk_tasks, workspace


class _Stop(Exception):
    """Raised by a test's progress hook to end a run early."""


def _die(task: tuple) -> None:
    """A chunk whose worker process dies (as if killed by the OOM killer)."""
    os.kill(os.getpid(), signal.SIGKILL)


def test_a_killed_worker_process_is_replaced_and_its_chunks_run_again(caplog):
    """SIGKILL to one of two pool workers after the first chunk: the pool starts again, the
    lost chunks run again, and the statistics equal one process's run of the same seed."""
    table = get_robot("scorbot").load_table()
    killed: list[int] = []

    def kill_one_worker(done: int, n: int) -> None:
        if not killed:
            pid = multiprocessing.active_children()[0].pid
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    with caplog.at_level(logging.WARNING, logger="kin.workspace.pool"):
        disturbed = workspace(
            table, 60_000, seed=11, chunk_size=2_000, workers=2, progress=kill_one_worker
        ).stats
    undisturbed = workspace(table, 60_000, seed=11, chunk_size=2_000).stats
    assert len(killed) == 1
    assert "died" in caplog.text and "run again" in caplog.text
    assert disturbed == undisturbed
    assert disturbed.n_samples == 60_000
    assert multiprocessing.active_children() == []


def test_a_chunk_that_always_kills_its_worker_stops_the_run(monkeypatch):
    """Every chunk kills its worker: after 3 losses of one chunk, RunFaultError, no worker left."""
    monkeypatch.setattr("kin.workspace.run._chunk", _die)  # forked workers inherit it
    table = get_robot("planar2").load_table()
    with pytest.raises(RunFaultError, match="died 3 times"):
        workspace(table, 4_000, chunk_size=1_000, workers=2)
    assert multiprocessing.active_children() == []


def test_ctrl_c_in_a_pool_run_leaves_no_worker():
    """KeyboardInterrupt after the first chunk: it propagates and the workers are gone at once."""
    table = get_robot("planar2").load_table()

    def interrupt(done: int, n: int) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        workspace(table, 10**18, chunk_size=1_000, workers=2, progress=interrupt)
    assert multiprocessing.active_children() == []


def test_chunks_are_made_lazily_and_seeded_by_their_index():
    """chunk_tasks of n = 1e18 yields at once; chunk i's seed is SeedSequence(seed).spawn's i-th."""
    table = get_robot("planar2").load_table()
    grid = WorkspaceGrid.around(table)
    tasks = chunk_tasks(table, grid, 10**18, 4, 1)
    first = [next(tasks) for _ in range(3)]
    assert [size for _, _, size, _ in first] == [1, 1, 1]
    for i, (child, (_, _, _, seed)) in enumerate(zip(np.random.SeedSequence(4).spawn(3), first)):
        assert np.array_equal(child.generate_state(4), seed.generate_state(4)), f"{i=}"
        assert np.array_equal(chunk_seed(4, i).generate_state(4), seed.generate_state(4))


@pytest.mark.parametrize("workers", [1, 2])
def test_a_huge_n_runs_in_bounded_memory_until_stopped(workers):
    """n = 1e18 in chunks of one sample, stopped after 20 chunks: it starts at once and the
    Python heap peaks below 100 MB (each chunk's voxel grids are about 10 MB)."""
    table = get_robot("planar2").load_table()
    calls: list[int] = []

    def stop_after_20(done: int, n: int) -> None:
        calls.append(done)
        if len(calls) == 20:
            raise _Stop

    tracemalloc.start()
    try:
        with pytest.raises(_Stop):
            workspace(table, 10**18, chunk_size=1, workers=workers, progress=stop_after_20)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert calls == list(range(1, 21))
    assert peak < 100e6, f"{peak=}"


@pytest.mark.parametrize(
    ("n", "chunk_size", "message"),
    [
        (1e18, 1_000, "n must be a whole number"),
        (0, 1_000, "n must be from 1"),
        (2**63, 1_000, "n must be from 1"),
        (1_000, 10**7, "chunk_size must be from 1 to 1,000,000"),
    ],
)
def test_bad_sizes_are_refused_at_once(n, chunk_size, message):
    """Non-integers and sizes out of range: KinError naming the argument, before any work."""
    with pytest.raises(KinError, match=message):
        workspace(get_robot("planar2").load_table(), n, chunk_size=chunk_size)


def test_cli_too_large_a_chunk_is_one_line(capsys):
    """--chunk-size beyond the largest chunk: one line naming it, exit 2."""
    code = workspace_main(["--robot", "planar2", "--n", "10", "--chunk-size", "100000000"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "chunk_size must be from 1" in err


@pytest.mark.parametrize(
    ("text", "hint"), [("1e18", "e.g. 1000000000000000000"), ("1.5", None), ("abc", None)]
)
def test_cli_n_in_scientific_notation_is_one_line_with_the_digits(capsys, text, hint):
    """--n 1e18: one line, exit 2, the number written out as the fix; 1.5 and abc: no hint."""
    with pytest.raises(SystemExit) as exit_:
        workspace_main(["--robot", "planar2", "--n", text])
    err = capsys.readouterr().err.strip().splitlines()
    assert exit_.value.code == 2 and len(err) == 1 and "not a whole number" in err[0], err
    assert (hint in err[0]) if hint else ("write it" not in err[0]), err


def _closing_cluster_hook(cluster, after: int):  # noqa: ANN001, ANN202
    """A progress hook that closes ``cluster`` (scheduler and workers) at its ``after``-th call."""
    calls: list[int] = []

    def hook(done: int, n: int) -> None:
        calls.append(done)
        if len(calls) == after:
            cluster.close()

    return hook, calls


def test_a_lost_dask_scheduler_is_a_run_fault():
    """The LocalCluster's scheduler closed after the second chunk: RunFaultError at once."""
    distributed = pytest.importorskip("distributed", reason="dask[distributed] not installed")
    table = get_robot("humanoid7").load_table()
    cluster = distributed.LocalCluster(
        n_workers=2,
        processes=False,
        threads_per_worker=1,
        dashboard_address=None,
        silence_logs=logging.CRITICAL,
    )
    hook, calls = _closing_cluster_hook(cluster, 2)
    with cluster, distributed.Client(cluster) as client:
        with pytest.raises(RunFaultError, match="lost the Dask scheduler"):
            workspace(table, 400_000, chunk_size=4_000, client=client, progress=hook)
    assert 2 <= len(calls) < 100


def test_a_lost_dask_scheduler_in_a_reach_map_is_a_run_fault():
    """kin reach's library on a LocalCluster closed after two chunks: RunFaultError."""
    distributed = pytest.importorskip("distributed", reason="dask[distributed] not installed")
    from kin import load_robot
    from kin.reach.map import reachability_map

    cluster = distributed.LocalCluster(
        n_workers=1,
        processes=False,
        threads_per_worker=1,
        dashboard_address=None,
        silence_logs=logging.CRITICAL,
    )
    hook, calls = _closing_cluster_hook(cluster, 3)  # (0, total) first, then two chunks
    with cluster, distributed.Client(cluster) as client:
        with pytest.raises(RunFaultError, match="lost the Dask scheduler"):
            reachability_map(
                load_robot("ur5"), 0.25, 4, scheduler=client, progress=hook, chunk_poses=8
            )
    assert 3 <= len(calls) < 20


@pytest.mark.parametrize(
    ("command", "target", "argv"),
    [
        ("workspace", "kin.workspace.monte_carlo.workspace", ["--robot", "planar2", "--n", "10"]),
        ("reach", "kin.reach.map.reachability_map", ["--robot", "ur5", "-o", "map.npz"]),
    ],
)
def test_cli_a_run_fault_is_one_line_and_exit_1(
    command, target, argv, monkeypatch, capsys, tmp_path
):
    """A RunFaultError during the run (a lost scheduler): one line, exit 1 (not 2, no traceback)."""
    from kin.commands import main

    def lost(*args, **kwargs):  # noqa: ANN002, ANN003
        raise RunFaultError("lost the Dask scheduler at tcp://x:8786 during the run")

    monkeypatch.setattr(target, lost)
    monkeypatch.chdir(tmp_path)
    code = main([command, *argv])
    err = capsys.readouterr().err
    assert code == 1, err
    assert err == f"kin {command}: error: lost the Dask scheduler at tcp://x:8786 during the run\n"
    assert list(tmp_path.iterdir()) == []


def test_the_estimate_comes_once_when_the_first_chunk_is_done():
    """estimate is called once, before the first progress report, with a positive duration."""
    events: list[tuple[str, float]] = []
    workspace(
        get_robot("planar2").load_table(),
        5_000,
        chunk_size=1_000,
        progress=lambda done, n: events.append(("progress", done)),
        estimate=lambda seconds: events.append(("estimate", seconds)),
    )
    assert [kind for kind, _ in events] == ["estimate"] + ["progress"] * 5
    assert events[0][1] > 0


@pytest.mark.parametrize(
    ("seconds", "text"),
    [(90, "1.5 minutes"), (3 * 3600, "3 hours"), (3 * 86400, "3 days"), (1e12, "31,688 years")],
)
def test_duration_text(seconds, text):
    """Durations in the largest unit that gives 2 or more (1e12 s / 31,557,600 s a year)."""
    from kin.commands.workspace import _duration_text

    assert _duration_text(seconds) == text


def test_cli_a_huge_n_says_how_long_and_stops_on_ctrl_c(monkeypatch, capsys):
    """--n 1e18 (written out): after the first chunk one line with the estimate in years; Ctrl-C
    after the second chunk: exit 130, 'interrupted' last, nothing on stdout."""
    import kin.workspace.run

    original = kin.workspace.run._chunk
    calls: list[int] = []

    def chunk_then_ctrl_c(task: tuple):  # noqa: ANN202
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return original(task)

    monkeypatch.setattr(kin.workspace.run, "_chunk", chunk_then_ctrl_c)
    argv = ["--robot", "planar2", "--n", str(10**18), "--chunk-size", "1000"]
    assert workspace_main(argv) == 130
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert lines[-1] == "kin workspace: interrupted"
    assert lines[0].startswith("kin workspace: 1,000,000,000,000,000,000 samples take about ")
    assert lines[0].endswith(" years at the first chunk's rate; Ctrl-C stops")
    assert captured.out == ""


def test_cli_a_short_run_says_nothing_of_its_duration(capsys):
    """A run of well under a minute prints no estimate."""
    assert workspace_main(["--robot", "planar2", "--n", "3000", "--json"]) == 0
    assert capsys.readouterr().err == ""

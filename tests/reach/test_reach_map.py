"""Reachability maps (``kin reach``): zero beyond the reach, per-call IK agrees voxel by voxel,
a Dask LocalCluster gives the local map, bad input is one line and exit 2, Ctrl-C leaves no file.

``KIN_REACH_CHECK_VOXELS`` sets how many random voxels are recomputed with per-call IK (default
40; the issue's check is 200).
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numpy as np
import pytest

from kin import KinError, load_robot
from kin.commands.reach import main as reach_main
from kin.ik import PoseTarget, get_solver
from kin.ik.reach import arm_reach
from kin.reach.map import (
    ReachMap,
    count_reached,
    load_reach_map,
    reachability_map,
    save_reach_map,
    super_fibonacci_rotations,
)

VOXEL = 0.2
K = 8
CHECK_VOXELS = int(os.environ.get("KIN_REACH_CHECK_VOXELS", "40"))


@pytest.fixture(scope="module")
def ur5_map() -> ReachMap:
    return reachability_map(load_robot("ur5"), VOXEL, K)


def test_orientations_are_rotations_spread_over_so3():
    """Super-Fibonacci rotations: orthonormal, det 1, deterministic, and evenly spread (the mean
    of each matrix entry of a uniform rotation is 0; no two rotations coincide)."""
    rotations = super_fibonacci_rotations(500)
    gram = np.einsum("kji,kjl->kil", rotations, rotations)
    assert np.abs(gram - np.eye(3)).max() < 1e-12
    assert np.allclose(np.linalg.det(rotations), 1.0)
    assert np.array_equal(rotations, super_fibonacci_rotations(500))
    assert np.abs(rotations.mean(axis=0)).max() < 0.02
    traces = np.einsum("aji,bji->ab", rotations[:50], rotations)  # trace(Ra^T Rb)
    np.fill_diagonal(traces[:, :50], -1.0)
    assert traces.max() < 3.0 - 1e-3  # angle between any two > ~1.8 degrees


def test_shape_units_and_zero_beyond_the_maximum_reach(ur5_map):
    """Centres on the voxel grid around the base origin; every centre beyond the maximum reach
    has index 0; indices are multiples of 1/K in [0, 1], some 1 and some 0 inside."""
    robot = load_robot("ur5")
    reach = arm_reach(robot)
    n = ur5_map.index.shape[0]
    assert ur5_map.centers_m.shape == (n, n, n, 3) and ur5_map.orientations == K
    assert np.allclose(np.diff(ur5_map.centers_m[:, 0, 0, 0]), VOXEL)
    assert np.allclose(ur5_map.centers_m[n // 2, n // 2, n // 2], reach.origin)
    assert (n // 2 + 0.5) * VOXEL >= reach.maximum
    distance = np.linalg.norm(ur5_map.centers_m - reach.origin, axis=-1)
    assert (distance > reach.maximum).any()
    assert np.all(ur5_map.index[distance > reach.maximum] == 0.0)
    assert np.allclose(ur5_map.index * K, np.round(ur5_map.index * K))
    assert ur5_map.index.max() == 1.0 and (ur5_map.index[distance < 0.5] > 0).any()


def test_random_voxels_agree_with_per_call_ik(ur5_map):
    """Random voxels inside the reach, recomputed with the documented per-call solver (one
    PoseTarget per orientation): the same index, exactly (the UR5 is solved in closed form)."""
    robot = load_robot("ur5")
    solver = get_solver(robot)
    reach = arm_reach(robot)
    rotations = super_fibonacci_rotations(K)
    centers = ur5_map.centers_m.reshape(-1, 3)
    index = ur5_map.index.reshape(-1)
    inside = np.flatnonzero(np.linalg.norm(centers - reach.origin, axis=1) <= reach.maximum)
    rng = np.random.default_rng(20)
    picked = rng.choice(inside, size=min(CHECK_VOXELS, len(inside)), replace=False)
    mismatches = []
    for i in picked.tolist():
        reached = sum(solver.solve(PoseTarget(centers[i], r)).success for r in rotations)
        if reached != round(index[i] * K):
            mismatches.append((centers[i].tolist(), reached, index[i] * K))
    assert mismatches == []
    assert len({round(index[i] * K) for i in picked.tolist()}) > 2  # not all 0 or all K


@pytest.mark.slow
def test_a_seven_joint_map_agrees_with_the_whole_per_call_pipeline():
    """Panda (a free-joint closed form, then numeric stages until a deadline per call): random
    voxels of a coarse map recomputed with the per-call solver from q = 0, every stage of it,
    give the same count (the map's first-stage-only answer misses none the pipeline finds), and
    a second map is the same (work-bounded, not timed)."""
    robot = load_robot("panda")
    k = 6
    panda_map = reachability_map(robot, 0.25, k)
    assert np.array_equal(reachability_map(robot, 0.25, k).index, panda_map.index)
    solver = get_solver(robot)
    reach = arm_reach(robot)
    rotations = super_fibonacci_rotations(k)
    centers = panda_map.centers_m.reshape(-1, 3)
    index = panda_map.index.reshape(-1)
    inside = np.flatnonzero(np.linalg.norm(centers - reach.origin, axis=1) <= reach.maximum)
    picked = np.random.default_rng(7).choice(inside, size=12, replace=False).tolist()
    picked += np.flatnonzero(index > 0)[:: max(1, (index > 0).sum() // 8)].tolist()[:8]
    counts = {
        i: sum(solver.solve(PoseTarget(centers[i], r), np.zeros(7)).success for r in rotations)
        for i in picked
    }
    mismatches = [(i, n, index[i] * k) for i, n in counts.items() if n != round(index[i] * k)]
    assert mismatches == []
    assert len(set(counts.values())) > 2  # not all 0 or all k
    # A pose whose only answer the scan from q = 0 misses (joint 7 within 3e-4 rad of its
    # limit): the free joints of the seed-table samples find it, as the per-call pipeline does.
    centre, rotations = np.array([[0.0, -0.8, 0.2]]), super_fibonacci_rotations(16)
    per_call = sum(solver.solve(PoseTarget(centre[0], r), np.zeros(7)).success for r in rotations)
    assert count_reached(robot, centre, rotations).tolist() == [per_call] == [8]


def test_a_local_dask_cluster_gives_the_local_map(ur5_map):
    """A LocalCluster of 2 workers (a Client, and its address) gives the local map exactly."""
    distributed = pytest.importorskip("distributed", reason="dask[distributed] not installed")
    robot = load_robot("ur5")
    cluster = distributed.LocalCluster(
        n_workers=2, processes=False, threads_per_worker=1, dashboard_address=None
    )
    with cluster, distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        on_dask = reachability_map(robot, VOXEL, K, scheduler=client, chunk_poses=400)
        by_address = reachability_map(robot, VOXEL, K, scheduler=cluster.scheduler_address)
    assert np.array_equal(on_dask.index, ur5_map.index)
    assert np.array_equal(by_address.index, ur5_map.index)
    assert np.array_equal(on_dask.centers_m, ur5_map.centers_m)


def test_chunking_does_not_change_the_map(ur5_map):
    """Chunks of one voxel give the map of the default chunks."""
    small = reachability_map(load_robot("ur5"), VOXEL, K, chunk_poses=1)
    assert np.array_equal(small.index, ur5_map.index)


def test_cli_writes_npz_png_and_json(tmp_path, capsys):
    """-o, --png, --json: the .npz and the JSON hold the same arrays; no temporary file is left;
    --unit cm takes the voxel in cm."""
    pytest.importorskip("matplotlib")
    out, png = tmp_path / "ur5.npz", tmp_path / "ur5.png"
    argv = ["--robot", "ur5", "--voxel", "20", "--unit", "cm", "--orientations", str(K)]
    assert reach_main([*argv, "-o", str(out), "--png", str(png), "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert {"voxel_m", "centers_m", "index", "orientations", "time_s"} <= set(document)
    assert document["voxel_m"] == pytest.approx(VOXEL) and document["orientations"] == K
    saved = load_reach_map(out)
    assert np.array_equal(saved.index, np.array(document["index"]))
    assert np.allclose(saved.centers_m, np.array(document["centers_m"]))
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ur5.npz", "ur5.png"]
    with np.load(out) as data:
        assert {"voxel_m", "centers_m", "index", "orientations", "time_s"} <= set(data.files)


def _exit_code(argv: list[str]) -> int:
    """The exit code of ``kin reach argv`` (argparse's errors exit through SystemExit)."""
    try:
        return reach_main(argv)
    except SystemExit as stop:
        return int(stop.code or 0)


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--voxel", "-0.1"], "--voxel"),
        (["--voxel", "0"], "--voxel"),
        (["--orientations", "0"], "--orientations"),
        (["--voxel", "0.0001"], "voxel"),
        (["--scheduler", "local-cluster:x"], "local-cluster:N"),
    ],
)
def test_cli_bad_input_is_one_line_and_exit_2(tmp_path, capsys, extra, needle):
    out = tmp_path / "m.npz"
    code = _exit_code(["--robot", "ur5", "-o", str(out), *extra])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and needle in err, err
    assert not out.exists()


@pytest.mark.parametrize("output", ["missing/m.npz", "m.txt", "."])
def test_cli_unwritable_output_is_one_line_and_exit_2(tmp_path, capsys, output):
    code = reach_main(["--robot", "ur5", "--voxel", "0.3", "-o", str(tmp_path / output)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and err.startswith("kin reach: error: -o"), err


def test_cli_read_only_folder_is_one_line_and_exit_2(tmp_path, capsys, monkeypatch):
    """A folder the user may not write (os.access says so: root writes anywhere): exit 2."""
    import kin.commands.output_file as output_file

    folder = tmp_path / "ro"
    folder.mkdir()
    monkeypatch.setattr(output_file.os, "access", lambda path, mode: Path(path) != folder)
    code = reach_main(["--robot", "ur5", "--voxel", "0.3", "-o", str(folder / "m.npz")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "not writable" in err, err
    assert list(folder.iterdir()) == []


def test_cli_ctrl_c_leaves_no_file(tmp_path, capsys, monkeypatch):
    """Ctrl-C after some chunks: one line, exit 130, neither the map nor a temporary file."""
    import kin.reach.map as reach_module

    calls = []
    real = reach_module.count_reached

    def interrupted(*args, **kwargs):  # noqa: ANN002, ANN003
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(reach_module, "count_reached", interrupted)
    monkeypatch.setattr(reach_module, "DEFAULT_CHUNK_POSES", 80)
    out = tmp_path / "m.npz"
    code = reach_main(["--robot", "ur5", "--voxel", "0.2", "--orientations", "8", "-o", str(out)])
    assert code == 130
    assert capsys.readouterr().err == "kin reach: interrupted\n"
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "scheduler",
    [
        "local",
        pytest.param("local-cluster:2", marks=pytest.mark.slow),
    ],
)
def test_sigint_to_a_running_command_leaves_no_file(tmp_path, scheduler):
    """SIGINT to the process group (a terminal's Ctrl-C) mid-run: exit 130, the last stderr line
    'kin reach: interrupted', no traceback, no map, no temporary file, no process left."""
    import signal
    import subprocess

    from support.cli_helper import kin_command
    from support.process_state import group_cpu_seconds, wait_until

    argv = ["reach", "--robot", "ur5", "--voxel", "0.02", "--orientations", "64"]
    process = subprocess.Popen(
        [*kin_command(), *argv, "--scheduler", scheduler, "-o", str(tmp_path / "m.npz")],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    try:
        # Mid-run by the work done (the CPU time of an idle machine's 3 s, or 8 s with a cluster,
        # the cluster's processes included), not by the clock: a loaded machine waits longer.
        work = 3.0 if scheduler == "local" else 10.0
        wait_until(lambda: group_cpu_seconds(process.pid) >= work, process, "mid-run")
        os.killpg(process.pid, signal.SIGINT)
        _, err = process.communicate(timeout=30)
        text = err.decode()
        assert process.returncode == 130, text
        assert text.strip().splitlines()[-1] == "kin reach: interrupted"
        assert "Traceback" not in text, text
        assert list(tmp_path.iterdir()) == []
        time.sleep(0.2)
        # Nothing left running (a zombie of an exited worker is not: this machine's init may
        # be slow to reap it).
        states = subprocess.run(
            ["ps", "-o", "stat=", "-g", str(process.pid)], capture_output=True, text=True
        ).stdout.split()
        assert [s for s in states if not s.startswith("Z")] == [], states
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)


def test_ctrl_c_while_writing_leaves_no_file(tmp_path, ur5_map, monkeypatch):
    """An interrupt inside the .npz write removes the temporary file and leaves no map."""

    def interrupted(*args, **kwargs):  # noqa: ANN002, ANN003
        raise KeyboardInterrupt

    monkeypatch.setattr(np, "savez_compressed", interrupted)
    with pytest.raises(KeyboardInterrupt):
        save_reach_map(ur5_map, tmp_path / "m.npz")
    assert list(tmp_path.iterdir()) == []


def test_small_voxels_and_small_arms_are_one_line_in_the_users_unit(tmp_path, capsys, monkeypatch):
    """--voxel 1 mm on UR5: one line in mm naming the smallest voxel; a 5-joint arm (whose full
    poses are measure zero): one line at once, before any solve (not minutes of failed solves);
    exit 2, no file."""
    import kin.ik.dispatch

    def no_solve(*args, **kwargs):
        raise AssertionError("the reach was solved: the 5-joint arm was not refused first")

    out = tmp_path / "m.npz"
    assert reach_main(["--robot", "ur5", "--voxel", "1", "--unit", "mm", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--voxel 1 mm" in err[0] and " mm: give --voxel " in err[0], err
    monkeypatch.setattr(kin.ik.dispatch, "get_solver", no_solve)
    assert reach_main(["--robot", "lab5", "--voxel", "0.1", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "5 joints" in err[0] and "6 or more" in err[0], err
    assert not out.exists()


def test_library_refuses_bad_arguments():
    robot = load_robot("ur5")
    for voxel, k in ((-0.1, 8), (float("nan"), 8), (0.2, 0), (0.2, 2.5)):
        with pytest.raises(KinError):
            reachability_map(robot, voxel, k)  # type: ignore[arg-type]


def test_preview_draws_the_reached_voxels_coloured_by_index(tmp_path, capsys, ur5_map):
    """kin preview --reach: one point per voxel with an index above 0, at its centre, coloured
    dark for low indices and yellow for 1; a map of another robot is one line and exit 2."""
    import base64
    import re

    umsgpack = pytest.importorskip("umsgpack")  # comes with meshcat
    pytest.importorskip("kin.viewer")
    from kin.commands.preview import main as preview_main
    from kin.viewer.reach_voxels import index_colors

    file = save_reach_map(ur5_map, tmp_path / "ur5.npz")
    page = tmp_path / "page.html"
    assert preview_main(["--robot", "ur5", "--reach", str(file), "--html", str(page)]) == 0
    encoded = re.findall(
        r'data:application/octet-binary;base64,([A-Za-z0-9+/=]+)"', page.read_text()
    )
    commands = [umsgpack.unpackb(base64.b64decode(data)) for data in encoded]
    (cloud,) = [c for c in commands if c.get("path") == "/meshcat/scene/markers/reach"]
    attributes = cloud["object"]["geometries"][0]["data"]["attributes"]
    points = np.frombuffer(attributes["position"]["array"].data, dtype=np.float32).reshape(-1, 3)
    colors = np.frombuffer(attributes["color"]["array"].data, dtype=np.float32).reshape(-1, 3)
    reached = ur5_map.index > 0
    assert np.allclose(points, ur5_map.centers_m[reached], atol=1e-6)
    assert np.allclose(colors, index_colors(ur5_map.index[reached]), atol=1e-6)
    assert np.allclose(index_colors([1.0])[0], [0.993, 0.906, 0.144])
    capsys.readouterr()
    code = preview_main(["--robot", "puma560", "--reach", str(file), "--html", str(page)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "--robot ur5" in err, err

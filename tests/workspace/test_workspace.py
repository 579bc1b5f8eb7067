"""Monte Carlo workspace: exact reproducibility across processes and Dask, reach against bounds,
areas and volumes against analytic values, the box against Pinocchio FK, the command's output."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from dh2urdf import ROBOTS, get_robot, parse_table
from kin import Configuration, KinError, load_robot
from kin.commands.workspace import main as workspace_main
from kin.workspace import WorkspaceGrid, chunk_sizes, reach_bound, workspace


def _cartesian_table():
    """Three orthogonal prismatic joints (strokes 0.2, 0.3, 0.4 m along world z, y, x)."""

    def row(theta: float, alpha: float, stroke: float) -> dict:
        return {
            "type": "prismatic",
            "a": 0.0,
            "alpha": alpha,
            "d": 0.0,
            "theta": theta,
            "limits": [0.0, stroke],
        }

    joints = [row(0, -90, 0.2), row(-90, -90, 0.3), row(0, 0, 0.4)]
    document = {"convention": "standard", "length_unit": "m", "angle_unit": "deg"}
    return parse_table({**document, "name": "cartesian", "joints": joints})


def test_same_statistics_in_one_process_and_a_process_pool():
    """--workers 2 gives exactly the statistics of one process (same seed and chunks)."""
    table = get_robot("scorbot").load_table()
    one = workspace(table, 40_000, seed=7, chunk_size=5_000).stats
    pool = workspace(table, 40_000, seed=7, chunk_size=5_000, workers=2).stats
    assert one == pool


def test_same_statistics_on_a_local_dask_cluster(capsys):
    """A LocalCluster of 2 workers (library, and --scheduler) gives one process's statistics."""
    distributed = pytest.importorskip("distributed", reason="dask[distributed] not installed")
    table = get_robot("humanoid7").load_table()
    one = workspace(table, 30_000, seed=3, chunk_size=4_000).stats
    cluster = distributed.LocalCluster(
        n_workers=2, processes=False, threads_per_worker=1, dashboard_address=None
    )
    with cluster, distributed.Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        on_dask = workspace(table, 30_000, seed=3, chunk_size=4_000, client=client).stats
        argv = ["--robot", "humanoid7", "--n", "30000", "--seed", "3", "--chunk-size", "4000"]
        assert workspace_main([*argv, "--json", "--scheduler", cluster.scheduler_address]) == 0
    assert one == on_dask
    assert json.loads(capsys.readouterr().out) == json.loads(json.dumps(one.to_dict()))


def test_another_seed_gives_other_samples():
    """Seeds matter: two seeds give different extremes."""
    table = get_robot("pickplace3").load_table()
    assert workspace(table, 2_000, seed=1).stats != workspace(table, 2_000, seed=2).stats


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_max_radius_within_the_reach_bound(name):
    """The reach never exceeds the sum of |a| + |d| (+ prismatic strokes, + tool offset)."""
    table = get_robot(name).load_table()
    stats = workspace(table, 20_000, seed=0).stats
    assert 0 < stats.max_radius_m <= stats.reach_bound_m + 1e-12, f"{name=}"
    assert stats.max_shoulder_distance_m <= stats.reach_bound_m + 1e-12, f"{name=}"
    assert stats.reach_bound_m == pytest.approx(reach_bound(table))


def test_planar2_reach_and_area():
    """planar2: radius 0.1 .. 0.5 m (l1 -+ l2) within 1%, area pi (0.5^2 - 0.1^2) m^2."""
    stats = workspace(get_robot("planar2").load_table(), 100_000, seed=0).stats
    assert 0.495 <= stats.max_radius_m <= 0.5 + 1e-12
    assert 0.1 - 1e-12 <= stats.min_radius_m <= 0.101
    analytic = math.pi * (0.5**2 - 0.1**2)
    perimeter = 2 * math.pi * (0.5 + 0.1)
    v = stats.voxel_size_m
    # Cells cut by the two circles count whole (at most perimeter x cell more); missed cells
    # are estimated by the half-sample error.
    assert analytic - 3 * stats.area_xy_error_m2 <= stats.area_xy_m2 <= analytic + perimeter * v
    assert abs(stats.area_xy_m2 / analytic - 1) < 0.05
    assert stats.bbox_min_m[2] == stats.bbox_max_m[2] == 0.0


def test_cartesian_box_volume():
    """Three orthogonal strokes 0.2 x 0.3 x 0.4 m: volume 0.024 m^3, within one voxel layer."""
    stats = workspace(_cartesian_table(), 400_000, seed=0, voxel_size_m=0.01).stats
    v = stats.voxel_size_m
    assert 0.024 - 3 * stats.volume_error_m3 <= stats.volume_m3 <= (0.2 + v) * (0.3 + v) * (0.4 + v)
    np.testing.assert_allclose(stats.bbox_max_m, [0.4, 0.3, 0.2], atol=0.01)
    np.testing.assert_allclose(stats.bbox_min_m, [0.0, 0.0, 0.0], atol=0.01)


def test_bounding_box_of_the_same_samples_through_pinocchio():
    """The box is that of Pinocchio's tool points at the same joint samples."""
    robot = load_robot("ur5")
    table, n, chunk = robot.table, 3_000, 1_000
    stats = workspace(table, n, seed=5, chunk_size=chunk).stats
    sizes = list(chunk_sizes(n, chunk))
    seeds = np.random.SeedSequence(5).spawn(len(sizes))
    points = []
    for size, seed in zip(sizes, seeds, strict=True):
        rng = np.random.default_rng(seed)
        q = table.lower + (table.upper - table.lower) * rng.random((size, table.dof))
        for qi in q:
            pose = Configuration(robot, qi).transform_frame_to_world("tool")
            points.append(pose.translation)
    points = np.array(points)
    np.testing.assert_allclose(stats.bbox_min_m, points.min(axis=0), atol=1e-12)
    np.testing.assert_allclose(stats.bbox_max_m, points.max(axis=0), atol=1e-12)
    radius = np.hypot(points[:, 0], points[:, 1])
    assert stats.max_radius_m == pytest.approx(radius.max(), abs=1e-12)


def test_too_fine_a_voxel_is_refused():
    """A voxel needing more than 256 per side raises KinError with the smallest valid size."""
    with pytest.raises(KinError, match="at least"):
        WorkspaceGrid.around(get_robot("ur5").load_table(), 0.001)


def test_cli_json_keys_name_units(capsys):
    """--json: SI values under unit-named keys; the text names --unit."""
    assert workspace_main(["--robot", "planar2", "--n", "20000", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    for key in ("max_radius_m", "min_radius_m", "volume_m3", "area_xy_m2", "bbox_min_m"):
        assert key in record, key
    assert record["n_samples"] == 20000 and 0.49 < record["max_radius_m"] <= 0.5
    assert workspace_main(["--robot", "planar2", "--n", "20000", "--unit", "mm"]) == 0
    out = capsys.readouterr().out
    assert "lengths in mm" in out and "mm^2" in out


def test_cli_writes_a_png(tmp_path, capsys):
    """-o writes a PNG (and no temporary file is left next to it)."""
    pytest.importorskip("matplotlib")
    target = tmp_path / "ws.png"
    assert workspace_main(["--robot", "pickplace3", "--n", "5000", "-o", str(target)]) == 0
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ws.png"]


def test_cli_ctrl_c_leaves_no_png(tmp_path, capsys, monkeypatch):
    """Ctrl-C while the PNG is written: one line, exit 130, no file."""
    pytest.importorskip("matplotlib")
    from matplotlib.figure import Figure

    def interrupted(*args, **kwargs):  # noqa: ANN002, ANN003
        raise KeyboardInterrupt

    monkeypatch.setattr(Figure, "savefig", interrupted)
    target = tmp_path / "ws.png"
    assert workspace_main(["--robot", "planar2", "--n", "1000", "-o", str(target)]) == 130
    assert capsys.readouterr().err == "kin workspace: interrupted\n"
    assert list(tmp_path.iterdir()) == []


def test_cli_scheduler_without_dask(monkeypatch, capsys):
    """--scheduler without dask installed: one line naming the extra, exit 2."""
    monkeypatch.setitem(sys.modules, "distributed", None)
    code = workspace_main(["--robot", "planar2", "--n", "10", "--scheduler", "tcp://x:8786"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert 'pip install "dh-kinematics[dask]"' in err


def test_import_kin_loads_neither_dask_nor_matplotlib():
    """import kin (and kin.workspace) stays light."""
    code = (
        "import sys, kin, kin.workspace, kin.commands.workspace; "
        "print(sorted(m for m in ('dask', 'distributed', 'matplotlib') if m in sys.modules))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], check=True, capture_output=True, text=True, cwd=Path.cwd()
    ).stdout
    assert out.strip() == "[]"


def test_progress_reports_every_chunk_up_to_n():
    """progress gets the samples done after each chunk, increasing to n."""
    calls: list[tuple[int, int]] = []
    table = get_robot("planar2").load_table()
    workspace(table, 2_500, chunk_size=1_000, progress=lambda done, n: calls.append((done, n)))
    assert calls == [(1_000, 2_500), (2_000, 2_500), (2_500, 2_500)]


def test_volume_says_when_it_has_not_converged():
    """humanoid7, 200k samples at the default voxels: the figure still grows (not converged),
    and Chao's estimate of the unseen voxels lies between it and a 16x larger run's figure."""
    from kin import load_robot
    from kin.workspace import workspace

    table = load_robot("humanoid7").table
    small = workspace(table, 200_000, seed=1).stats
    large = workspace(table, 3_200_000, seed=2).stats
    assert not small.volume_converged
    assert small.volume_error_m3 > 0.05 * small.volume_m3
    assert small.volume_m3 < small.volume_estimate_m3 < large.volume_m3


def test_volume_converges_with_few_voxels_per_sample():
    """pickplace3 with 3 cm voxels and 2M samples: converged, the estimate equals the figure
    within 1 %, and a second seed agrees within 1 %."""
    from kin import load_robot
    from kin.workspace import workspace

    table = load_robot("pickplace3").table
    first = workspace(table, 2_000_000, seed=1, voxel_size_m=0.03).stats
    second = workspace(table, 2_000_000, seed=2, voxel_size_m=0.03).stats
    assert first.volume_converged and second.volume_converged
    assert abs(first.volume_estimate_m3 - first.volume_m3) < 0.01 * first.volume_m3
    assert abs(first.volume_m3 - second.volume_m3) < 0.01 * first.volume_m3

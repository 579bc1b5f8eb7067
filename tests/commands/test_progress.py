"""The long commands' progress bar: count/total and time left on a terminal, redrawn in place at
most ten times a second, ended by a newline; nothing on a pipe or a file, nothing with --quiet."""

from __future__ import annotations

import io
import re

import pytest

from kin.commands.progress import REDRAW_INTERVAL, ProgressBar, format_seconds


class FakeTerminal(io.StringIO):
    """A stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


class FakeClock:
    """A monotonic clock the test moves by hand [s]."""

    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def _frames(text: str) -> list[str]:
    """The redrawn lines of a bar's output (split at the carriage returns), without padding."""
    return [frame.rstrip() for frame in text.rstrip("\n").split("\r") if frame]


def test_bar_shows_count_total_and_time_left_then_a_newline():
    """Half done after 10 s: 10 s left (rate so far); done: the time in all; then a newline."""
    stream, clock = FakeTerminal(), FakeClock()
    with ProgressBar("kin test", "poses", stream=stream, clock=clock) as bar:
        bar(0, 2000)
        clock.now += 10.0
        bar(1000, 2000)
        clock.now += 10.0
        bar(2000, 2000)
    text = stream.getvalue()
    frames = _frames(text)
    assert text.startswith("\r") and text.endswith("\n") and text.count("\n") == 1, repr(text)
    assert frames[0].endswith("0/2,000 poses   0% --:-- left"), frames
    assert frames[1].startswith("kin test: [############------------]"), frames
    assert frames[1].endswith("1,000/2,000 poses  50% 0:10 left"), frames
    assert frames[2].endswith("2,000/2,000 poses 100% 0:20 in all"), frames


def test_redrawn_at_most_ten_times_a_second_and_the_last_count_always():
    """Calls closer than REDRAW_INTERVAL draw nothing, except the final count."""
    stream, clock = FakeTerminal(), FakeClock()
    bar = ProgressBar("kin test", stream=stream, clock=clock)
    for done in range(0, 100):
        bar(done, 100)
        clock.now += REDRAW_INTERVAL / 4
    bar(100, 100)
    bar.close()
    frames = _frames(stream.getvalue())
    # 25 s of calls at 40 per second: one frame per 0.1 s, the first and the last.
    assert 25 <= len(frames) <= 27, len(frames)
    assert frames[-1].split("] ")[1].startswith("100/100"), frames[-1]


def test_a_shorter_line_is_padded_over_the_longer_one():
    """A redraw shorter than the line before covers it (no stale characters left on screen)."""
    stream, clock = FakeTerminal(), FakeClock()
    bar = ProgressBar("kin test", stream=stream, clock=clock)
    bar(5, 10**9)
    clock.now += 3600.0 * 20  # a long time left: H:MM:SS
    bar(6, 10**9)
    clock.now += 1.0
    bar(10**9, 10**9)
    raw = [frame for frame in stream.getvalue().split("\r") if frame]
    assert len(raw[2]) >= len(raw[1].rstrip()) and raw[2].rstrip().endswith("in all")


@pytest.mark.parametrize("quiet", [False, True])
def test_silent_on_a_pipe_and_with_quiet(quiet):
    """A stream that is no terminal gets nothing; a terminal with quiet gets nothing."""
    stream = FakeTerminal() if quiet else io.StringIO()
    with ProgressBar("kin test", quiet=quiet, stream=stream) as bar:
        bar(0, 10)
        bar(10, 10)
    assert stream.getvalue() == ""


def test_format_seconds():
    assert [format_seconds(s) for s in (0, 0.2, 59.5, 61, 3600, 3725)] == [
        "0:00",
        "0:01",
        "1:00",
        "1:01",
        "1:00:00",
        "1:02:05",
    ]


# --- through the commands -----------------------------------------------------------------------

_BAR = re.compile(r"\[[#-]+\] ([\d,]+)/([\d,]+) (poses|samples|samples of the path) +\d+% ")


def _run(monkeypatch, capsys, main, argv, terminal=True):  # noqa: ANN001
    """``main(argv)`` with stderr a fake terminal (or a plain buffer): (code, stderr text)."""
    import sys

    stream = FakeTerminal() if terminal else io.StringIO()
    monkeypatch.setattr(sys, "stderr", stream)
    code = main(argv)
    capsys.readouterr()
    return code, stream.getvalue()


def _check_bar(err: str, prog: str, total: int | None = None) -> None:
    frames = _frames(err)
    assert err.startswith("\r") and err.endswith("\n") and err.count("\n") == 1, repr(err)
    assert all(frame.startswith(f"{prog}: [") for frame in frames), frames
    counts = [tuple(int(v.replace(",", "")) for v in _BAR.search(f).groups()[:2]) for f in frames]
    assert counts[0][0] == 0 and counts[-1][0] == counts[-1][1], counts  # from 0 to the total
    assert total is None or counts[-1][1] == total, counts
    assert "left" in frames[0] and frames[-1].endswith("in all"), frames


def test_reach_draws_the_bar_on_a_terminal(tmp_path, monkeypatch, capsys):
    """kin reach on a terminal: poses from 0 to the total (voxels within reach x K)."""
    from kin import load_robot
    from kin.commands.reach import main
    from kin.ik.reach import arm_reach
    from kin.reach.map import _grid

    argv = [
        "--robot",
        "ur5",
        "--voxel",
        "0.3",
        "--orientations",
        "4",
        "-o",
        str(tmp_path / "m.npz"),
    ]
    code, err = _run(monkeypatch, capsys, main, argv)
    reach = arm_reach(load_robot("ur5"))
    centers = _grid(reach.origin, 0.3, reach.maximum).reshape(-1, 3)
    inside = int(((centers - reach.origin) ** 2).sum(axis=1).__le__(reach.maximum**2).sum())
    assert code == 0
    _check_bar(err, "kin reach", inside * 4)


@pytest.mark.parametrize("terminal, quiet", [(False, False), (True, True)])
def test_reach_is_silent_on_a_pipe_and_with_quiet(tmp_path, monkeypatch, capsys, terminal, quiet):
    from kin.commands.reach import main

    argv = [
        "--robot",
        "ur5",
        "--voxel",
        "0.3",
        "--orientations",
        "4",
        "-o",
        str(tmp_path / "m.npz"),
    ]
    code, err = _run(monkeypatch, capsys, main, argv + ["--quiet"] * quiet, terminal)
    assert code == 0 and err == ""


def test_workspace_draws_the_bar_on_a_terminal(monkeypatch, capsys):
    """kin workspace on a terminal: samples up to --n; silent with --quiet."""
    from kin.commands.workspace import main

    argv = ["--robot", "ur5", "--n", "30000", "--chunk-size", "10000"]
    code, err = _run(monkeypatch, capsys, main, argv)
    assert code == 0
    _check_bar(err, "kin workspace", 30000)
    code, err = _run(monkeypatch, capsys, main, [*argv, "--quiet"])
    assert code == 0 and err == ""


_PATH = ["--from", "0.4", "0.1", "0.3", "--rpy", "3.14", "0", "0"]
_PATH += ["--to", "0.4", "-0.2", "0.4", "--rpy", "3.14", "0", "0", "--steps", "300", "--json"]


@pytest.mark.parametrize("robot", ["ur5", "panda"])  # closed form; differential steps
def test_path_draws_the_bar_on_a_terminal(monkeypatch, capsys, robot):
    """kin path on a terminal: samples from 0 to all of them (the path is followed); silent on
    a pipe and with --quiet."""
    from kin.commands.path import main

    code, err = _run(monkeypatch, capsys, main, ["--robot", robot, *_PATH])
    assert code == 0, err
    _check_bar(err, "kin path", 301)
    for terminal, extra in ((False, []), (True, ["--quiet"])):
        code, err = _run(monkeypatch, capsys, main, ["--robot", robot, *_PATH, *extra], terminal)
        assert code == 0 and err == ""


def test_path_library_progress_counts_every_sample():
    """follow_path's progress: non-decreasing counts from 0 to the number of samples."""
    import numpy as np

    from kin import load_robot
    from kin.ik import PoseTarget
    from kin.path import follow_path, polyline

    turn = np.diag([1.0, -1.0, -1.0])
    path = polyline([PoseTarget([0.4, 0.1, 0.3], turn), PoseTarget([0.4, -0.2, 0.4], turn)], 50)
    calls: list[tuple[int, int]] = []
    result = follow_path(load_robot("ur5"), path, progress=lambda d, t: calls.append((d, t)))
    assert result.success
    done = [d for d, _ in calls]
    assert done[0] == 0 and done[-1] == len(path) and done == sorted(done)
    assert {t for _, t in calls} == {len(path)} and len(calls) >= len(path)

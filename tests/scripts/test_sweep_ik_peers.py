"""sweep_ik_peers.py: argument errors, the grids, a tiny sweep per peer, and Ctrl-C."""

import pytest
from support.scripts_helper import exit_code, load_script


def sweep():
    return load_script("sweep_ik_peers")


@pytest.mark.parametrize(
    "script, argv, needle",
    [
        ("sweep_ik_peers", ["--n", "0"], "must be at least 1"),
        ("sweep_ik_peers", ["--n", "x"], "not a whole number"),
        ("sweep_ik_peers", ["--seed", "1.5"], "invalid int value"),
        ("sweep_ik_peers", ["--peers", "ours"], "invalid choice"),
        ("sweep_ik_peers", ["--quick", "yes"], "unrecognized arguments"),
        ("bench_ik_humanoid7", ["--rtb-k", "0"], "must be positive"),
        ("bench_ik_humanoid7", ["--rtb-ilimit", "0"], "must be at least 1"),
        ("bench_ik_humanoid7", ["--rtb-method", "lm"], "invalid choice"),
        ("bench_ik_humanoid7", ["--tracik-solver", "Fast"], "invalid choice"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(script, argv, needle, capsys):
    assert exit_code(load_script(script).main, argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    assert needle in err and "Traceback" not in err


def test_grids_have_the_asked_size_and_copyable_options():
    """36 ik_LM and 12 TRAC-IK settings; each one's options parse back to its own values."""
    module = sweep()
    bench = module._benchmark()
    rtb, tracik = module.rtb_grid(quick=False), module.tracik_grid(quick=False)
    assert (len(rtb), len(tracik)) == (36, 12)
    assert (len(module.rtb_grid(quick=True)), len(module.tracik_grid(quick=True))) == (3, 2)
    parser = bench.get_argument_parser()
    for setting in rtb:
        args, kw = parser.parse_args(setting.options.split()), setting.build.keywords
        assert (args.rtb_method, args.rtb_k, args.rtb_ilimit, args.rtb_searches) == (
            kw["method"],
            kw["k"],
            kw["ilimit"],
            kw["searches"],
        )
    for setting in tracik:
        args, kw = parser.parse_args(setting.options.split()), setting.build.keywords
        assert (args.tracik_solver, args.tracik_timeout) == (kw["solver_type"], kw["timeout_ms"])


def test_best_prefers_success_then_the_lower_median():
    module = sweep()
    setting = module.rtb_grid(quick=True)[0]

    def result(success, median):
        return module.Result(setting, "full pose", "q = 0", success, median, 2 * median)

    fast, slow, surer = result(0.9, 0.1), result(0.9, 0.2), result(1.0, 5.0)
    assert module.best([slow, fast]) is fast
    assert module.best([fast, surer, slow]) is surer


def _tiny_sweep(peers, capsys):
    assert sweep().main(["--n", "3", "--quick", "--peers", peers]) == 0
    captured = capsys.readouterr()
    assert "[1/" in captured.err and "Traceback" not in captured.err
    return captured.out


@pytest.mark.peer
def test_tiny_rtb_sweep_prints_the_table_and_the_winners(capsys):
    pytest.importorskip("roboticstoolbox")
    out = _tiny_sweep("rtb", capsys)
    head, _, winners = out.partition("best setting per peer, task and start")
    rows = [line for line in head.splitlines() if line.startswith("RTB ik_LM")]
    assert len(rows) == 3 * 2 * 2  # 3 settings x 2 tasks x 2 starts
    best = [line for line in winners.splitlines() if line.startswith("RTB ik_LM")]
    assert len(best) == 4 + 1  # per task and start, then the single best setting
    assert all("--rtb-method" in line and "--rtb-searches" in line for line in best)


@pytest.mark.peer
def test_tiny_tracik_sweep_prints_the_table_and_the_winners(capsys):
    pytest.importorskip("trac_ik")
    out = _tiny_sweep("tracik", capsys)
    head, _, winners = out.partition("best setting per peer, task and start")
    rows = [line for line in head.splitlines() if line.startswith("TRAC-IK")]
    assert len(rows) == 2 * 2 and all("full pose" in row for row in rows)
    best = [line for line in winners.splitlines() if line.startswith("TRAC-IK")]
    assert len(best) == 2 + 1 and all("--tracik-solver" in line for line in best)


@pytest.mark.peer
def test_ctrl_c_prints_the_finished_runs_and_exits_130(capsys, monkeypatch):
    """An interrupt in the second run keeps the first run's row and the winners, exit 130."""
    pytest.importorskip("roboticstoolbox")
    module = sweep()
    bench = module._benchmark()
    real_run, calls = bench.run, []

    def run_then_interrupt(*args):
        calls.append(args)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real_run(*args)

    monkeypatch.setattr(bench, "run", run_then_interrupt)
    assert module.main(["--n", "2", "--quick", "--peers", "rtb"]) == 130
    captured = capsys.readouterr()
    assert captured.err.strip().endswith("sweep_ik_peers.py: interrupted")
    rows = [line for line in captured.out.splitlines() if line.startswith("RTB ik_LM")]
    assert len(rows) == 1 + 1  # the finished run's row and its winner line
    assert "interrupted: results of 1 of 3 settings" in captured.out

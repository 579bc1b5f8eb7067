"""scripts/bench_cli.py: one short run prints every row with a positive figure."""

from __future__ import annotations

import re

import pytest
from support.scripts_helper import exit_code, load_script


def test_bench_cli_prints_every_row(capsys):
    """Six wall times [s] (two on a table file), two --stdin rates [/s], the start-up split."""
    assert load_script("bench_cli").main(["--runs", "1", "--targets", "20"]) == 0
    out = capsys.readouterr().out
    walls = [float(v) for v in re.findall(r" (\d+\.\d+) s ", out + " ")]
    assert len(walls) == 6 and all(0 < wall < 30 for wall in walls), out
    rates = re.findall(r" (\d+) /s .*success (\d+)/(\d+)", out)
    assert len(rates) == 2 and all(int(r) > 0 and ok == total for r, ok, total in rates), out
    split = re.search(r"import kin.ik ([\d.]+), load_robot humanoid7 ([\d.]+)", out)
    assert split and float(split.group(1)) > 0, out


@pytest.mark.parametrize("argv", [["--runs", "0"], ["--targets", "-3"], ["--runs", "x"]])
def test_bench_cli_bad_counts_exit_2(argv, capsys):
    """A zero, negative or non-numeric count: exit 2, one line on stderr."""
    assert exit_code(load_script("bench_cli").main, argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err

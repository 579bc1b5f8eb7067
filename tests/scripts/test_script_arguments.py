"""Counts and budgets on the command line must be positive: exit 2 with one line on stderr."""

import pytest
from support.scripts_helper import exit_code, load_script


@pytest.mark.parametrize(
    "script, argv, needle",
    [
        ("bench_ik", ["--calls", "0"], "must be at least 1"),
        ("bench_ik", ["--repeat", "-1"], "must be at least 1"),
        ("bench_fk", ["--number", "x"], "not a whole number"),
        ("bench_ik_humanoid7", ["--n", "0"], "must be at least 1"),
        ("bench_ik_humanoid7", ["--timeout", "nan"], "not a finite number"),
        (
            "solve_ik",
            ["--robot", "humanoid7", "--target", "0.4", "0.2", "-0.1", "--timeout", "-5"],
            "must be positive",
        ),
    ],
)
def test_non_positive_counts_exit_2_with_one_line(script, argv, needle, capsys):
    """A zero, negative or non-numeric count or budget is refused before any work is done."""
    assert exit_code(load_script(script).main, argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    assert needle in err and "Traceback" not in err

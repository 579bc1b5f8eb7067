"""The compiled twins of the 6R families on the cases without a UR or spherical wrist, against NumPy.

``_pieper_arms.c`` (the Pieper family's twin) on its intersecting, parallel and general arms and
``_three_parallel.c`` (the three-parallel family's) on its general arms (``a5 != 0``) against their
family's NumPy algorithm (``compiled=False``, :mod:`six_r_twin_parity`), on the seeded random
tables of ``test_ik_pieper.py`` and ``test_ik_three_parallel.py`` in both conventions (random
lengths, twists, offsets, base and tool): ``solve`` to 1e-10 rad with NaN rows alike,
``solve_batch``, and :class:`ClosedFormSolver`'s compiled path against its Python path
(Pinocchio as the judge); each twin's layout against its Python fields.

Skipped when a twin is not built (no C compiler at install) or SciPy's LAPACK is missing.
"""

from __future__ import annotations

import pytest
from support import pieper_arms, three_parallel_arms
from support.arm_tables import assert_layout_matches
from support.six_r_twin_parity import assert_batch_parity, assert_solve_parity, assert_solver_parity
from support.spherical_wrist_arms import arm_table as pieper_table

from kin.ik.analytic.six_r import pieper, three_parallel
from kin.ik.analytic.six_r.pieper import Pieper6R
from kin.ik.analytic.six_r.three_parallel import ThreeParallel6R

#: Each twin (None when not built or SciPy's LAPACK is missing), its structure, its tables.
TWINS = {
    "pieper": (pieper._arms_twin("general"), Pieper6R, pieper_arms.random_table),
    "three_parallel": (
        three_parallel._general_twin(),
        ThreeParallel6R,
        three_parallel_arms.random_table,
    ),
}
ARMS = [("pieper", (family, convention, seed)) for family in ("intersecting", "parallel", "general")
        for convention in ("standard", "modified") for seed in (0, 1)] + [
        ("three_parallel", (family, convention, seed)) for family in ("general", "classic")
        for convention in ("standard", "modified") for seed in (0, 1)]  # fmt: skip


def structure(kind: str, arm: tuple[str, str, int]):
    """The table and its structure, solved by the twin of ``kind``."""
    twin, cls, random_table = TWINS[kind]
    if twin is None:
        pytest.skip(f"the compiled twin of {kind} is not built")
    table = random_table(*arm)
    found = cls.recognise(table)
    assert found.compiled_twin is twin, f"{kind=} {arm=}"
    return table, found


@pytest.mark.parametrize(("kind", "arm"), ARMS)
def test_twin_solve_equals_numpy(kind, arm):
    """The twin's branches are the NumPy algorithm's, target by target (1e-10 rad, NaN alike)."""
    assert_solve_parity(*structure(kind, arm), f"{arm=}")


@pytest.mark.parametrize(("kind", "arm"), ARMS)
def test_twin_batch_equals_numpy_batch(kind, arm):
    """The twin's solve_batch is its solve target by target, and the NumPy batch to 1e-9 rad."""
    assert_batch_parity(*structure(kind, arm))


@pytest.mark.parametrize(("kind", "arm"), ARMS[::3])
@pytest.mark.parametrize("narrow", [False, True])
def test_compiled_solver_equals_python_solver(kind, arm, narrow):
    """ClosedFormSolver's compiled path returns what its Python path (Pinocchio judge) returns."""
    assert_solver_parity(structure(kind, arm)[0], narrow, f"{arm=}")


@pytest.mark.parametrize("kind", sorted(TWINS))
def test_layout_matches_the_python_fields(kind):
    """The twin's LAYOUT is the fields the structure packs, in order and size."""
    _, found = structure(kind, next(arm for k, arm in ARMS if k == kind))
    assert_layout_matches(found, TWINS[kind][0])


@pytest.mark.parametrize(
    ("table", "cls", "kind"),
    [
        (lambda: pieper_table("puma560"), Pieper6R, "pieper"),
        (
            lambda: three_parallel_arms.random_table("intersecting", "standard", 0),
            ThreeParallel6R,
            "three_parallel",
        ),
    ],
)
def test_the_special_cases_share_their_family_s_twin(table, cls, kind):
    """The spherical wrist and the UR case run in their family's one twin, under their case's code."""
    twin = TWINS[kind][0]
    if twin is None:
        pytest.skip(f"the compiled twin of {kind} is not built")
    found = cls.recognise(table())
    assert type(found) is not cls and found.compiled_twin is twin, f"{kind=}"
    assert found.c_params.size == twin.PARAM_COUNT
    start = next(start for name, start, _ in twin.LAYOUT if name == "family")
    assert found.c_params[start] == {"pieper": 3.0, "three_parallel": 0.0}[kind], f"{kind=}"

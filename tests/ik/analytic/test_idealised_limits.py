"""An idealised arm polishes only the branches inside or near the joint limits.

A branch outside its limits by more than :data:`OUTSIDE_MARGIN` in every copy ``+ 2 pi k`` is
rejected whether it is polished or not, so the closed form judges it unpolished
(:mod:`kin.ik.analytic.branch_verification`; its listing in ``rejected``:
``test_idealised_rejected.py``). The check is compared with the limit rule's own
:func:`~kin.ik.limit_rule.nearest_copy`, and the answers inside the limits with those of
polishing every branch, each measured by the plain NumPy DH product of the rounded table
(:mod:`dh_reference`), an independent FK.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference, rotation_angle

from kin import load_robot
from kin.ik import PoseTarget, PositionTarget, get_solver
from kin.ik.analytic.branch_verification import OUTSIDE_MARGIN
from kin.ik.analytic.closed_form import ClosedFormSolver
from kin.ik.analytic.idealised_fallback import IdealisedPolish
from kin.ik.limit_rule import nearest_copy

AL5D = Path(__file__).parents[2] / "data" / "toolbox" / "al5d.toml"


@pytest.fixture(scope="module")
def rounded(tmp_path_factory):
    """The AL5D table file with its twists rounded as the corpus URDF writes them."""
    text = AL5D.read_text(encoding="utf-8")
    text = text.replace("alpha = 3.141592653589793", "alpha = 3.141592653")
    text = text.replace("alpha = 1.5707963267948966", "alpha = 1.570796325")
    path = tmp_path_factory.mktemp("al5d") / "al5d_rounded.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_outside_agrees_with_the_limit_rule(rounded):
    """``BranchVerifier.far_outside`` is True exactly when no copy is within the margin of the limits."""
    solver = get_solver(load_robot(rounded))
    assert isinstance(solver, ClosedFormSolver) and solver.idealised is not None
    offsets, lower, upper = solver.arm.offsets, solver.arm.lower, solver.arm.upper
    rng = np.random.default_rng(3)
    seen = {True: 0, False: 0}
    for _ in range(2000):
        q = rng.uniform(np.subtract(lower, 4.0), np.add(upper, 4.0))
        # some joints just inside or outside the margin
        k = rng.integers(len(q))
        q[k] = (
            (lower[k], upper[k])[rng.integers(2)]
            + rng.choice((-1, 1)) * OUTSIDE_MARGIN * (1.0 + rng.choice((-1e-3, 1e-3)))
            + 2 * np.pi * rng.integers(-2, 3)
        )
        expected = not all(
            nearest_copy(v, 0.0, lo - OUTSIDE_MARGIN, hi + OUTSIDE_MARGIN)[1]
            for v, lo, hi in zip(q.tolist(), lower, upper)
        )
        thetas = tuple(np.add(q, offsets).tolist())
        assert solver.verifier.far_outside(thetas) is expected, f"{q=}"
        seen[expected] += 1
    assert min(seen.values()) > 100, seen


@pytest.mark.parametrize("kind", ["position", "pose"])
def test_skipping_the_polish_keeps_every_answer(rounded, monkeypatch, caplog, kind):
    """The answers are those of polishing every branch, and reach the target (reference FK).

    No branch is dropped with a warning (an unpolished one would miss by the idealisation's
    error), and the status is the same.
    """
    robot = load_robot(rounded)
    solver = get_solver(robot)
    reference = load_reference(rounded)
    rng = np.random.default_rng(7)
    targets = []
    for q in rng.uniform(robot.lower, robot.upper, (150, robot.nq)):
        T = fk_frames(reference, q)[0, -1]
        targets.append(
            PositionTarget(T[:3, 3]) if kind == "position" else PoseTarget(T[:3, 3], T[:3, :3])
        )
    seed = np.clip(np.zeros(robot.nq), robot.lower, robot.upper)
    skipped = [solver.solve(target, seed) for target in targets]
    assert not [r for r in caplog.records if "misses the target" in r.getMessage()]
    calls = {"skipped": 0}

    def every_branch(self, target, branches, seed, p, r, quiet=False, near=np.inf):  # noqa: ANN001
        calls["skipped"] += sum(bool(self.verifier.far_outside(t)) for t, _ in branches.thetas)
        return self.verifier.verify(
            target, self.polished(branches, target, near), seed, p, r, quiet
        )

    monkeypatch.setattr(IdealisedPolish, "verify_polished", every_branch)
    full = [solver.solve(target, seed) for target in targets]
    assert calls["skipped"] > 50, calls  # the skip is exercised
    for target, a, b in zip(targets, skipped, full):
        assert a.success == b.success and a.status == b.status
        assert len(a.solutions) == len(b.solutions)
        for x, y in zip(a.solutions, b.solutions):
            assert np.abs(x.q - y.q).max() <= 1e-9
            reached = fk_frames(reference, x.q)[0, -1]
            assert np.linalg.norm(reached[:3, 3] - target.position) < 1e-9
            if kind == "pose":
                assert rotation_angle(reached[:3, :3], target.rotation) < 1e-9

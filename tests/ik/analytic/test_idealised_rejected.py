"""A rounded arm's answer lists the branches it reaches only outside the limits, polished or not.

The AL5D table with pi written as 3.141592653 and pi/2 as 1.570796325 (as the corpus URDF does)
and its limits tightened to +-1.2 rad is solved on its idealised geometry (:mod:`.idealised`). A
branch far outside the limits is judged without its polish (:mod:`.branch_verification`); the
answer must still list it in ``rejected``, with a reason naming the joint, as polishing every
branch did. The reference is independent of the solver: Pinocchio's FK on a model built here from
the rounded arm's URDF, the limits read from the table file (:mod:`dh_reference`), and a
Gauss-Newton refinement written here that takes each unpolished branch onto the target.
"""

from __future__ import annotations

import logging
import math
import re
from pathlib import Path

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference, rotation_angle
from support.idealised_reference import (
    AL5D,
    ROUNDINGS,
    Reference,
    arm_file,
    reference_outside,
    rounded_text,
    targets_of,
)

from kin import load_robot
from kin.ik import get_solver
from kin.ik.analytic.branch_verification import OUTSIDE_MARGIN, UNPOLISHED_MISS
from kin.ik.analytic.closed_form import ClosedFormSolver
from kin.ik.analytic.idealised import idealise
from kin.ik.analytic.idealised_fallback import IdealisedPolish

TARGETS = 120


@pytest.fixture(scope="module", params=ROUNDINGS, ids=["corpus", "4_decimals"])
def rounded(tmp_path_factory, request) -> Path:
    """The rounded AL5D table file, limits +-1.2 rad."""
    path = tmp_path_factory.mktemp("al5d") / "al5d_rounded.toml"
    path.write_text(rounded_text(*request.param), encoding="utf-8")
    return path


def polish_every_branch(self, target, branches, seed, p, r, quiet=False, near=math.inf):  # noqa: ANN001
    """Every branch polished, then verified: the rule before branches were judged unpolished."""
    return self.verifier.verify(target, self.polished(branches, target, near), seed, p, r, quiet)


@pytest.mark.parametrize(
    ("arm", "kind"),
    [
        ("al5d_corpus", "position"),
        ("al5d_corpus", "pose"),
        ("al5d_4_decimals", "position"),
        ("al5d_4_decimals", "pose"),
        ("puma560_4_decimals", "pose"),
    ],
)
def test_rejected_branches_are_listed_as_when_every_branch_was_polished(
    arm, kind, tmp_path, monkeypatch, caplog
):
    """Every rejected branch is outside the limits and reaches the target (Pinocchio), as before.

    An unpolished one (its reason set) names a joint more than the margin outside in every copy,
    states its errors as Pinocchio measures them, and is taken onto the target by the reference's
    own refinement without coming near the limits. The rejected branches are those of polishing
    every branch; on a pose of the 4-joint AL5D (more equations than joints) also those whose
    polish would stall off the pose, each with its reason and errors. The valid answers are the
    same.
    """
    rounded = arm_file(arm, tmp_path)
    robot = load_robot(rounded)
    solver = get_solver(robot)
    assert isinstance(solver, ClosedFormSolver) and solver.idealised is not None
    reference = Reference(rounded)
    square = kind == "position" or robot.nq >= 6  # as many joints as equations, or more
    rng = np.random.default_rng(5)
    qs = rng.uniform(reference.lower, reference.upper, (TARGETS, robot.nq))
    targets = targets_of(reference, kind, qs)
    seed = np.zeros(robot.nq)
    bound_p, bound_r = solver.verifier.miss_bound  # type: ignore[misc]
    kept = []
    far = IdealisedPolish.polish_each

    def counted(self, thetas, target, near, keep_far=False):  # noqa: ANN001
        moved, left = far(self, thetas, target, near, keep_far)
        kept.append(len(left))
        return moved, left

    monkeypatch.setattr(IdealisedPolish, "polish_each", counted)
    with caplog.at_level(logging.WARNING):
        results = [solver.solve(target, seed) for target in targets]
    assert not [r for r in caplog.records if "misses the target" in r.getMessage()]
    monkeypatch.setattr(IdealisedPolish, "verify_polished", polish_every_branch)
    before = [solver.solve(target, seed) for target in targets]
    unpolished = extra = 0
    largest = 0.0  # the refinement's largest move [rad]
    for target, result, old in zip(targets, results, before):
        assert result.success and old.success, f"{target=}"  # the PUMA's stretched elbow too
        assert [s.branch for s in result.solutions] == [s.branch for s in old.solutions]
        for new_q, old_q in zip(result.solutions, old.solutions):
            assert np.abs(new_q.q - old_q.q).max() < 1e-12
        labels = [s.branch for s in result.rejected]
        old_labels = [s.branch for s in old.rejected]
        if square:
            assert sorted(labels) == sorted(old_labels), f"{target=}"
        else:  # those and the ones whose polish stalls off the pose (they say so)
            assert set(old_labels) <= set(labels), f"{target=}"
            extra += len(labels) - len(old_labels)
        for solution in result.rejected:
            position, angle = reference.errors(solution.q, target)
            beyond = reference.beyond(solution.q)
            assert not solution.within_limits and beyond.max() > 0.0, f"{solution=}"
            assert abs(position - solution.position_error) < 1e-12
            assert abs(angle - (solution.rotation_error or 0.0)) < 1e-9
            if not solution.reason:  # polished: on target
                assert position <= 1e-9 and angle <= 1e-9, f"{solution=}"
                continue
            unpolished += 1
            joint = re.search(r"joint '([^']+)'", solution.reason).group(1)  # type: ignore[union-attr]
            assert beyond[reference.names.index(joint)] > OUTSIDE_MARGIN, f"{solution=}"
            assert position <= bound_p and angle <= bound_r, f"{solution=}"
            assert position > 1e-9 or angle > 1e-9  # else it would be on target as it is
            refined = reference.refine(solution.q, target)
            reached = reference.errors(refined, target)
            moved = np.abs(refined - solution.q).max()
            if square:
                assert max(reached) < 1e-12, f"{solution=} {reached=}"
            assert moved < OUTSIDE_MARGIN, f"{solution=} {moved=}"  # the rule's premise
            largest = max(largest, moved)
            assert reference.beyond(refined)[reference.names.index(joint)] > 0.0, f"{solution=}"
    assert sum(kept) > TARGETS, f"{sum(kept)=}"  # the rule is exercised
    if max(bound_p, bound_r) > 2e-6:  # 4 decimals (the corpus' are on target as they are)
        assert unpolished > TARGETS // 4, f"{unpolished=}"
    print(
        f"{arm} {kind}: {unpolished} with a reason (refined by <= {largest:.2g} rad), {extra} more"
    )


def test_a_target_reached_only_outside_the_limits_is_judged_on_polished_branches(
    rounded, monkeypatch
):
    """No valid branch of a position: every branch polished, on target (Pinocchio) and outside.

    The answer is that of polishing every branch. (The free pitch's sweep answers
    ``out_of_reach`` when no pitch has a branch inside the limits: issue 32 item 4's "every
    branch of a closed form outside the limits".)
    """
    robot = load_robot(rounded)
    solver = get_solver(robot)
    reference = Reference(rounded)
    qs = np.random.default_rng(8).uniform(-2.5, 2.5, (200, robot.nq))
    targets = targets_of(reference, "position", qs[reference_outside(reference, qs)])
    seed = np.zeros(robot.nq)
    results = [solver.solve(target, seed) for target in targets]
    monkeypatch.setattr(IdealisedPolish, "verify_polished", polish_every_branch)
    before = [solver.solve(target, seed) for target in targets]
    outside = 0
    for target, result, old in zip(targets, results, before):
        assert (result.success, result.status) == (old.success, old.status), f"{target=}"
        if result.status != "outside_limits":
            continue
        outside += 1
        assert len(result.rejected) == len(old.rejected)
        for solution, polished in zip(in_order(result.rejected), in_order(old.rejected)):
            assert solution.branch == polished.branch
            assert not solution.reason, f"{solution=}"
            assert np.abs(solution.q - polished.q).max() < 1e-12
            assert max(reference.errors(solution.q, target)) <= 1e-9, f"{solution=}"
            assert reference.beyond(solution.q).max() > 0.0, f"{solution=}"
    assert outside > 50, f"{outside=}"


def in_order(solutions: tuple) -> list:
    """The solutions sorted by branch label, then joint vector."""
    return sorted(solutions, key=lambda s: (s.branch, s.q.round(6).tolist()))


@pytest.mark.parametrize(("pi", "half_pi"), [("3.141592653", "1.570796325"), ("3.1416", "1.5708")])
def test_snap_bounds_hold_at_every_joint_vector(pi, half_pi, tmp_path):
    """The tool of the exact table (independent DH product) is within the bounds of the rounded one.

    Sampled over every joint vector (limits aside); the bounds are not loose by more than 100x.
    """
    path = tmp_path / "al5d_rounded.toml"
    path.write_text(rounded_text(pi, half_pi, limit=None), encoding="utf-8")
    ideal = idealise(load_robot(path).table)
    assert ideal is not None
    q = np.random.default_rng(2).uniform(-np.pi, np.pi, (4000, 4))
    exact = fk_frames(load_reference(AL5D), q)[:, -1]
    rounded_fk = fk_frames(load_reference(path), q)[:, -1]
    moved = np.linalg.norm(exact[:, :3, 3] - rounded_fk[:, :3, 3], axis=1).max()
    turned = rotation_angle(exact[:, :3, :3], rounded_fk[:, :3, :3]).max()
    assert moved <= ideal.position_bound <= 100 * moved, (moved, ideal.position_bound)
    assert turned <= ideal.rotation_bound <= 100 * turned, (turned, ideal.rotation_bound)


def test_the_miss_bound_is_far_under_the_margin(rounded):
    """The bound on an unpolished branch's miss stays 100x under the margin, 1e4x with the corpus'."""
    solver = get_solver(load_robot(rounded))
    assert max(solver.verifier.miss_bound) <= OUTSIDE_MARGIN * 1e-2  # type: ignore[attr-defined]
    assert UNPOLISHED_MISS < max(solver.verifier.miss_bound)  # type: ignore[attr-defined]

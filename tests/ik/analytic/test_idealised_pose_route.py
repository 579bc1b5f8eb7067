"""An idealised closed-form arm's full poses by its own branches, polished (the pose route).

The AL5D table with pi written as 3.141592653 and pi/2
as 1.570796325 (as the corpus URDF does) is solved on the
idealised geometry; its full poses go to the closed form's branches, polished on the true chain
(:mod:`kin.ik.analytic.idealised`), not to the partial-pose solver. Every answer is measured by
the plain NumPy DH product of the rounded table (:mod:`dh_reference`), an independent FK.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference, rotation_angle

from kin import load_robot
from kin.ik import PoseTarget, get_solver
from kin.ik.analytic.closed_form import ClosedFormSolver
from kin.ik.analytic.idealised import polish

AL5D = Path(__file__).parents[2] / "data" / "toolbox" / "al5d.toml"
TARGETS = 100


@pytest.fixture(scope="module")
def rounded(tmp_path_factory):
    """The AL5D table file with its twists rounded as the corpus URDF writes them."""
    text = AL5D.read_text(encoding="utf-8")
    text = text.replace("alpha = 3.141592653589793", "alpha = 3.141592653")
    text = text.replace("alpha = 1.5707963267948966", "alpha = 1.570796325")
    assert text.count("alpha = 3.141592653\n") == 3 and text.count("alpha = 1.570796325\n") == 1
    path = tmp_path_factory.mktemp("al5d") / "al5d_rounded.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_rounded_arm_full_poses_take_the_closed_form_branches(rounded, monkeypatch):
    """Every FK pose is solved by the polished branches; the partial-pose solver is never asked."""
    robot = load_robot(rounded)
    solver = get_solver(robot)
    assert isinstance(solver, ClosedFormSolver) and solver.idealised is not None
    monkeypatch.setattr(
        ClosedFormSolver, "partial", property(lambda self: pytest.fail("partial-pose solver asked"))
    )
    reference = load_reference(rounded)
    rng = np.random.default_rng(11)
    found_original = 0
    for q in rng.uniform(robot.lower, robot.upper, (TARGETS, robot.nq)):
        T = fk_frames(reference, q)[0, -1]
        result = solver.solve(PoseTarget(T[:3, 3], T[:3, :3]))
        assert result.success, f"{q=} {result.message}"
        assert result.method == "closed_form_polished", f"{q=} {result.method=}"
        for solution in result.solutions:
            reached = fk_frames(reference, solution.q)[0, -1]
            assert np.linalg.norm(reached[:3, 3] - T[:3, 3]) < 1e-9, f"{q=} {solution=}"
            assert rotation_angle(reached[:3, :3], T[:3, :3]) < 1e-9, f"{q=} {solution=}"
            assert np.all(solution.q >= robot.lower) and np.all(solution.q <= robot.upper)
        found_original += any(np.abs(s.q - q).max() < 1e-6 for s in result.solutions)
    assert found_original == TARGETS, f"{found_original=}"


def test_polish_gives_up_far_from_the_target(rounded):
    """A start beyond ``give_up`` gives NaN; a near one is polished as without ``give_up``."""
    robot = load_robot(rounded)
    judge = get_solver(robot).verifier.judge  # type: ignore[attr-defined]
    reference = load_reference(rounded)
    q = np.array([0.3, -0.4, 0.5, 0.2])
    T = fk_frames(reference, q)[0, -1]
    args = (judge.model, judge.data, judge.frame_id)
    far = q + np.array([0.5, 0.0, 0.0, 0.0])
    assert np.isnan(polish(*args, far, T[:3, 3], T[:3, :3], give_up=1e-2)).all()
    assert np.abs(polish(*args, far, T[:3, 3], T[:3, :3]) - q).max() < 1e-10
    near = q + 1e-4
    polished = polish(*args, near, T[:3, 3], T[:3, :3], give_up=1e-2)
    assert np.abs(polished - q).max() < 1e-10
    assert np.array_equal(polished, polish(*args, near, T[:3, 3], T[:3, :3]))

"""The numeric solver's settings are one frozen value; its stages read a frozen context (issue 34)."""

from __future__ import annotations

import dataclasses
import inspect
import re

import numpy as np
import pytest

from kin import Configuration, load_robot
from kin.ik import NumericIK, PoseTarget
from kin.ik.numeric.context import NumericContext
from kin.ik.numeric.settings import NumericSettings
from kin.ik.numeric.solver import STAGES


@pytest.fixture(scope="module")
def panda():
    return load_robot("panda")


def test_every_setting_is_documented_with_its_default_in_one_place():
    """The docstring's ``Attributes:`` names exactly the fields, in order (21 settings)."""
    # cleandoc: Python 3.13 strips the docstring's indentation itself, older ones do not
    doc = inspect.cleandoc(NumericSettings.__doc__ or "")
    documented = re.findall(r"^    (\w+): ", doc.split("Attributes:")[1], re.MULTILINE)
    fields = [field.name for field in dataclasses.fields(NumericSettings)]
    assert documented == fields
    assert len(fields) == 21


def test_settings_are_frozen_and_keep_steps_as_a_tuple():
    """A setting cannot be changed after the fact; a list of scan steps is kept as a tuple."""
    settings = NumericSettings(closed_form_steps=[0.1, 0.02])  # type: ignore[arg-type]
    assert settings.closed_form_steps == (0.1, 0.02)
    with pytest.raises(dataclasses.FrozenInstanceError):
        settings.nearest = 3  # type: ignore[misc]


def test_keyword_arguments_build_the_settings(panda):
    """``NumericIK(robot, near_seed=True, ...)`` as before: the keywords become its settings."""
    solver = NumericIK(panda, near_seed=True, nearest=5, prepare=False)
    assert solver.settings == NumericSettings(near_seed=True, nearest=5, prepare=False)
    assert solver.nearest == 5 and solver.near_seed is True  # read-only aliases
    given = NumericIK(panda, NumericSettings(nearest=4), prepare=False)
    assert given.settings.nearest == 4 and given.settings.prepare is False
    with pytest.raises(TypeError, match="nearst"):
        NumericIK(panda, nearst=4)
    with pytest.raises(AttributeError, match="no_such_setting"):
        _ = solver.no_such_setting


def test_the_context_is_frozen_and_holds_the_resolved_handles(panda):
    """The stages' context: the settings, the limits as floats, the closed form as resolved."""
    solver = NumericIK(panda, prepare=False)
    context = solver.context
    assert isinstance(context, NumericContext) and context.settings is solver.settings
    assert context.lows == tuple(panda.model.lowerPositionLimit.tolist())
    assert context.highs == tuple(panda.model.upperPositionLimit.tolist())
    assert context.closed_form is not None  # Panda: the spherical-shoulder free-joint form
    assert solver.closed_form is context.closed_form  # the alias reads the context first
    with pytest.raises(dataclasses.FrozenInstanceError):
        context.nq = 6  # type: ignore[misc]
    without = NumericIK(panda, closed_form=False, prepare=False).context
    assert without.closed_form is None and without.compiled is False


def test_a_stage_run_on_the_context_alone_answers_the_pose(panda):
    """The seed-table stage given only the context and a search reaches a pose FK produced."""
    from kin.ik.numeric.numeric_target import NumericTarget
    from kin.ik.numeric.search import Search

    solver = NumericIK(panda, closed_form=False)
    q = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.5])
    pose = Configuration(panda).fk(q)
    target = NumericTarget.from_target(PoseTarget(pose.translation, pose.rotation))
    search = Search(solver.context, target, 1e-5, 1e-4, 5.0, table=solver.table)
    result = STAGES[1].run(solver.context, search)
    assert result is not None and result.success
    reached = Configuration(panda).fk(result.solutions[0].q)
    assert np.linalg.norm(reached.translation - pose.translation) < 1e-5

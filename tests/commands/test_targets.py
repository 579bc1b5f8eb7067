"""kin.commands.targets: the command line's target terms and its refusals, in its words."""

from __future__ import annotations

import pytest

from kin.commands.targets import Takes, build_target
from kin.ik.exceptions import TargetError
from kin.ik.targets.target import PitchTarget, PoseTarget, PositionTarget


def test_the_command_refuses_a_kind_before_it_builds_the_target():
    """build_target with a solver's kinds: a pitch for a pose-only solver, named in CLI terms."""
    takes = Takes("arm6", 6, (PoseTarget, PositionTarget))
    with pytest.raises(TargetError, match=r"'arm6' \(6 joints\) takes: --rpy, --quat, or a "):
        build_target([0.2, 0.0, 0.1], pitch=0.3, takes=takes)
    with pytest.raises(TargetError, match="a full pose needs at least 6 joints"):
        build_target([0.2, 0.0, 0.1], rpy=[0, 0, 0], takes=Takes("arm5", 5, (PitchTarget,)))
    target, option = build_target([0.2, 0.0, 0.1], quat=[1, 0, 0, 0], takes=takes)
    assert isinstance(target, PoseTarget) and option == "--quat"

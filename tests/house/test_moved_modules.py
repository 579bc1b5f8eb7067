"""Modules moved into kin's folders (issue 46): the old import paths that docs named still work.

``kin.mimic_arm`` and ``kin.reach_map`` became :mod:`kin.mimic.arm` and :mod:`kin.reach.map`;
the old modules hand on the same objects with a DeprecationWarning, as do ``kin.ik.target`` and
``kin.ik.collision_aware`` (now in the folders ``kin/ik/targets/`` and ``kin/ik/collision/``). ``kin.workspace`` became a
package whose face holds the old module's names.
"""

from __future__ import annotations

import importlib
import sys

import pytest


@pytest.mark.parametrize(
    ("old", "new", "names"),
    [
        ("kin.mimic_arm", "kin.mimic.arm", ["MimicArm", "load_arm", "load_mimic_arm"]),
        ("kin.reach_map", "kin.reach.map", ["reachability_map", "save_reach_map", "ReachMap"]),
        ("kin.ik.target", "kin.ik.targets.target", ["PoseTarget", "PositionTarget", "AxisTarget"]),
        (
            "kin.ik.collision_aware",
            "kin.ik.collision.collision_aware",
            ["CollisionAwareSolver", "collision_reason"],
        ),
    ],
)
def test_an_old_path_warns_and_hands_on_the_same_objects(old, new, names):
    sys.modules.pop(old, None)
    with pytest.warns(DeprecationWarning, match=new.replace(".", r"\.")):
        moved = importlib.import_module(old)
    current = importlib.import_module(new)
    assert all(getattr(moved, name) is getattr(current, name) for name in names)


def test_the_workspace_package_keeps_the_old_module_names():
    import kin.workspace
    from kin.workspace import monte_carlo

    for name in ("workspace", "WorkspaceGrid", "chunk_sizes", "chunk_seed", "reach_bound"):
        assert getattr(kin.workspace, name) is getattr(monte_carlo, name)

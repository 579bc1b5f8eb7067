"""A DH arm's fitted volumes are drawn see-through, so its joint markers and triads show.

Without it, UR5's housings (issue 43) hid every orange joint axis and DH triad in the preview:
test_preview_screenshot.py's ur5-b picture had 0.02 % warm pixels, then 0.2 % with this.
"""

from __future__ import annotations

import numpy as np
import pytest
from support.stick_arms import stick_robot

from kin import load_robot

viewer_module = pytest.importorskip("kin.viewer")
see_through = pytest.importorskip("kin.viewer.see_through")

ORANGE = (0.9, 0.5, 0.1)  # the joint markers' color in the DH writer's URDF


def alphas(viewer) -> dict[str, float]:
    """Geometry name -> the alpha the viewer draws it with."""
    return {g.name: float(g.meshColor[3]) for g in viewer.visual_model.geometryObjects}


def test_housings_are_see_through_and_the_joints_opaque():
    """UR5: one see-through piece per housing of its table; the six joint markers stay opaque."""
    robot = load_robot("ur5")
    viewer = viewer_module.RobotViewer(robot)
    drawn = alphas(viewer)
    housings = sum(len(row.housings) for row in robot.table.rows)
    faded = [name for name, alpha in drawn.items() if alpha < 1.0]
    assert housings > 0 and len(faded) == housings, (housings, faded)
    assert all(drawn[name] == pytest.approx(see_through.BODY_OPACITY) for name in faded)
    joints = [
        g.name
        for g in viewer.visual_model.geometryObjects
        if np.allclose(g.meshColor[:3], ORANGE, atol=1e-6)
    ]
    assert len(joints) == robot.nq and all(drawn[name] == 1.0 for name in joints), joints


def test_thin_sticks_stay_opaque():
    """The 1 cm sticks hide no joint marker: nothing of the housing-less UR5 fades."""
    viewer = viewer_module.RobotViewer(stick_robot("ur5"))
    assert all(alpha == 1.0 for alpha in alphas(viewer).values()), alphas(viewer)

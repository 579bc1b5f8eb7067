"""kin.batch_forward_kinematics against Pinocchio (the URDF) and the independent DH product."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import fk_configurations
from support.dh_reference import fk_frames, load_reference

from dh2urdf import ROBOTS, get_robot, parse_table
from kin import Configuration, JointVectorError, load_robot, robot_from_table
from kin.batch_fk import batch_forward_kinematics, batch_tool_positions


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_every_frame_matches_the_reference_product(name):
    q = fk_configurations(name)
    expected = fk_frames(load_reference(get_robot(name).table_path), q)
    got = batch_forward_kinematics(load_robot(name).table, q, frames=True)
    assert got.shape == expected.shape
    assert np.abs(got - expected).max() < 1e-12


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_tool_matches_pinocchio(name):
    robot = load_robot(name)
    q = fk_configurations(name)[:200]
    got = batch_forward_kinematics(robot.table, q)
    for qi, T in zip(q, got):
        pose = Configuration(robot, qi).transform_frame_to_world("tool")
        assert np.abs(T[:3, :3] - pose.rotation).max() < 1e-12
        assert np.abs(T[:3, 3] - pose.translation).max() < 1e-12
    assert np.array_equal(batch_tool_positions(robot.table, q), got[:, :3, 3])


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_prismatic_joint_matches_pinocchio(convention):
    table = parse_table(
        {
            "name": f"rpr_{convention}",
            "convention": convention,
            "length_unit": "m",
            "angle_unit": "deg",
            "joints": [
                {
                    "type": "revolute",
                    "a": 0.1,
                    "alpha": 90,
                    "d": 0.3,
                    "theta": 10,
                    "limits": [-90, 90],
                },
                {
                    "type": "prismatic",
                    "a": 0.05,
                    "alpha": -90,
                    "d": 0.2,
                    "theta": 90,
                    "limits": [0, 0.5],
                },
                {
                    "type": "revolute",
                    "a": 0.2,
                    "alpha": 30,
                    "d": 0.0,
                    "theta": 0,
                    "limits": [-180, 180],
                },
            ],
            "tool": {"xyz": [0.0, 0.0, 0.1], "rpy": [10.0, 20.0, 30.0]},
        }
    )
    robot = robot_from_table(table)
    rng = np.random.default_rng(3)
    q = rng.uniform(table.lower, table.upper, size=(100, 3))
    got = batch_forward_kinematics(table, q)
    for qi, T in zip(q, got):
        assert (
            np.abs(T - Configuration(robot, qi).transform_frame_to_world("tool").homogeneous).max()
            < 1e-12
        )


def test_one_vector_and_bad_shapes():
    table = load_robot("ur5").table
    assert batch_forward_kinematics(table, np.zeros(6)).shape == (1, 4, 4)
    with pytest.raises(JointVectorError, match="'ur5' has 6 joints"):
        batch_forward_kinematics(table, np.zeros((4, 5)))

"""A URDF arm whose chain holds mimic joints: FK and IK over the independent joints only.

A mimic joint ``<mimic joint="L" multiplier="m" offset="c"/>`` in series on the chain turns with
its leader: ``q = m q_L + c``. A DH table has one independent variable per row, so the coupled
chain is a table with a row per joint (mimic rows included, :func:`~dh2urdf.urdf_to_dh.
table_from_chain`) plus the coupling (:meth:`dh2urdf.urdf_chain.UrdfChain.expand`); the user's
joint vector holds the independent joints only, base to tip.

- FK: the table's DH product at the expanded joint vector (checked on loading against Pinocchio's
  FK of the URDF to 1e-9).
- IK: damped least squares on the coupled Jacobian (the table model's Jacobian times the
  coupling's ``d q_all / d q``), from the seed then seeded random starts, inside the limits
  (the independent joints' own, narrowed so that every mimic joint stays inside its own). An
  answer is returned only when Pinocchio's model of the original URDF built with mimic joints
  (:class:`pinocchio.JointModelMimic`) puts the tip on the target within the judge's tolerances.

``kin fk`` and ``kin ik`` load such a chain through :func:`kin.robot_model.load_arm` (IK by
:class:`kin.mimic.solver.MimicSolver`); the other commands, whose joint units, seeds and closed
forms read one variable per table row, refuse it in one line.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from dh2urdf import DHTable
from dh2urdf.urdf_chain import UrdfChain

from ..exceptions import FrameError, JointVectorError, ModelLoadError, NotWithinLimitsError
from ..ik.judge import rotation_error
from ..ik.result import IKSolution
from ..robot_model import RobotModel, load_robot, robot_from_chain, robot_from_table, urdf_file
from .descent import CoupledChain, MimicSearch, search

# MimicSearch lives in mimic_descent (the search's stages); it stays importable from here.
__all__ = ["MimicArm", "MimicSearch", "load_arm", "load_mimic_arm", "mimic_arm_from_chain"]


@dataclass(frozen=True, eq=False)
class MimicArm:
    """A chain with mimic joints, ready for FK and IK over its independent joints.

    Attributes:
        chain: The URDF chain (every joint, mimic ones with their coupling).
        table: DH table with a row per joint of the chain (SI units).
        robot: The table's model (one variable per row): the solver's Jacobians.
        reference: Pinocchio's model of the original URDF with mimic joints: the judge.
        lower: Lower limits of the independent joints [rad] or [m], narrowed by the mimic ones.
        upper: Upper limits of the independent joints [rad] or [m], narrowed by the mimic ones.
    """

    chain: UrdfChain
    table: DHTable
    robot: RobotModel
    reference: pin.Model
    lower: np.ndarray
    upper: np.ndarray

    @property
    def name(self) -> str:
        """Robot name (its table's, as :func:`kin.load_robot` names a URDF chain)."""
        return self.table.name

    @property
    def frame_names(self) -> tuple[str, ...]:
        """Frames :meth:`frame_pose` knows: ``"tool"`` (the tip link), then the URDF's links."""
        links = (f.name for f in self.reference.frames if f.type == pin.FrameType.BODY)
        return ("tool", *links)

    @property
    def nq(self) -> int:
        """Number of independent joint values."""
        return len(self.chain.independent)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Names of the independent joints, base to tip."""
        return tuple(joint.name for joint in self.chain.independent)

    @property
    def coupling(self) -> np.ndarray:
        """``d q_all / d q``: (joints of the chain) x (independent joints), the multipliers."""
        index = {name: i for i, name in enumerate(self.joint_names)}
        matrix = np.zeros((len(self.chain.joints), self.nq))
        for row, joint in enumerate(self.chain.joints):
            if joint.mimic is None:
                matrix[row, index[joint.name]] = 1.0
            else:
                matrix[row, index[joint.mimic.leader]] = joint.mimic.multiplier
        return matrix

    def fk(self, q: npt.ArrayLike) -> np.ndarray:
        """``T_base_tip`` (4x4, [m]) at the independent joints' values ``q`` [rad] or [m]."""
        product = np.array(self.table.T_world_base)
        for row, value in zip(self.table.rows, self.chain.expand(self._vector(q)), strict=True):
            product = product @ row.transform(self.table.convention, float(value))  # beta too
        return product @ self.table.T_last_tool

    def reference_fk(self, q: npt.ArrayLike) -> np.ndarray:
        """``T_base_tip`` (4x4, [m]) by Pinocchio's mimic model of the original URDF."""
        return np.array(self.frame_pose(q, "tool").homogeneous)

    def frame_pose(self, q: npt.ArrayLike, frame: str = "tool") -> pin.SE3:
        """``T_base_frame`` [m] by Pinocchio's mimic model of the original URDF.

        Args:
            q: The independent joints' values [rad] or [m].
            frame: A link of the URDF, or ``"tool"``: the chain's tip link.

        Raises:
            JointVectorError: Not one finite value per independent joint.
            FrameError: No link of that name; the message lists them.
        """
        model = self.reference
        name = self.chain.tip if frame == "tool" else frame
        if not model.existFrame(name, pin.FrameType.BODY):
            raise FrameError(frame, self.frame_names)
        data = model.createData()
        full = pin.neutral(model)
        for joint, value in zip(self.chain.independent, self._vector(q), strict=True):
            entry = model.joints[model.getJointId(joint.name)]
            if entry.nq == 2:  # continuous: (cos, sin)
                full[entry.idx_q : entry.idx_q + 2] = (math.cos(value), math.sin(value))
            else:
                full[entry.idx_q] = value
        pin.framesForwardKinematics(model, data, full)
        base = model.getFrameId(self.chain.base, pin.FrameType.BODY)
        return data.oMf[base].actInv(data.oMf[model.getFrameId(name, pin.FrameType.BODY)])

    def limit_violations(self, q: npt.ArrayLike) -> list[NotWithinLimitsError]:
        """The joints of the chain, mimic ones included, outside their own limits at ``q``.

        Args:
            q: The independent joints' values [rad] or [m].
        """
        full = self.chain.expand(self._vector(q))
        return [
            NotWithinLimitsError(
                joint.name,
                float(value),
                joint.lower,
                joint.upper,
                "rad" if joint.joint_type == "revolute" else "m",
            )
            for joint, value in zip(self.chain.joints, full, strict=True)
            if not (joint.continuous or joint.lower <= value <= joint.upper)
        ]

    def within_limits(self, q: npt.ArrayLike) -> bool:
        """Whether every joint of the chain, mimic ones included, is inside its limits."""
        full = self.chain.expand(self._vector(q))
        return all(
            joint.continuous or joint.lower <= value <= joint.upper
            for joint, value in zip(self.chain.joints, full, strict=True)
        )

    def solve_ik(
        self,
        T_base_target: npt.ArrayLike,
        seed: npt.ArrayLike | None = None,
        *,
        restarts: int = 40,
        max_iter: int = 200,
        rng_seed: int = 0,
    ) -> IKSolution | None:
        """Independent joint values that put the tip on ``T_base_target``, or None.

        Args:
            T_base_target: Target pose of the tip link in the base link (4x4, [m]).
            seed: First start [rad] or [m] (default: the middle of the limits).
            restarts: Random starts after the seed (seeded by ``rng_seed``).
            max_iter: Damped least-squares steps per start.
            rng_seed: Seed of the random starts.

        Returns:
            An :class:`IKSolution` inside every joint's limits whose tip pose, by Pinocchio's
            mimic model of the URDF, is within :data:`~kin.ik.judge.POSITION_TOLERANCE` [m] and
            :data:`~kin.ik.judge.ROTATION_TOLERANCE` [rad] of the target; None when no start
            converges there.
        """
        target = np.asarray(T_base_target, dtype=float)
        found = self.search(
            target[:3, 3],
            target[:3, :3],
            seed,
            restarts=restarts,
            max_iter=max_iter,
            rng_seed=rng_seed,
        )
        return found.answer

    def search(
        self,
        position: npt.ArrayLike,
        rotation: npt.ArrayLike | None,
        seed: npt.ArrayLike | None = None,
        *,
        restarts: int = 40,
        max_iter: int = 200,
        rng_seed: int = 0,
        timeout: float | None = None,
        near: Callable[[], npt.ArrayLike] | None = None,
    ) -> MimicSearch:
        """Damped least squares on the coupled Jacobian, from the seed, then near and random starts.

        The stages are :mod:`kin.mimic.descent`'s (:func:`~kin.mimic.descent.search`).

        Args:
            position: Target position of the tip link in the base link [m], shape (3,).
            rotation: Target axes of the tip link in the base link (3x3), or None: the
                orientation is free.
            seed: First start [rad] or [m] (default: the middle of the limits); clipped into
                the limits.
            restarts: Random starts after the seed (seeded by ``rng_seed``).
            max_iter: Damped least-squares steps per start.
            rng_seed: Seed of the random starts.
            timeout: No new start after this time [s] (the first one always runs); None: all.
            near: Gives the starts to try after the seed, before random ones, within
                ``restarts`` (:func:`kin.mimic.starts.sample_table`'s samples nearest the
                target); called only when the seed's descent fails. None: random ones only.

        Returns:
            The first answer judged on target inside every joint's limits (Pinocchio's mimic
            model of the URDF, :data:`~kin.ik.judge.POSITION_TOLERANCE` [m],
            :data:`~kin.ik.judge.ROTATION_TOLERANCE` [rad]), the best attempt, and the counts.
        """
        oriented = rotation is not None
        goal = pin.SE3(
            np.asarray(rotation, dtype=float) if oriented else np.eye(3),  # type: ignore[arg-type]
            np.asarray(position, dtype=float),
        )
        first = (
            0.5 * (self.lower + self.upper)
            if seed is None
            else np.clip(self._vector(seed), self.lower, self.upper)
        )
        chain = CoupledChain(
            self.robot, self.chain.expand, self.coupling, self.lower, self.upper, self._judged
        )
        return search(chain, goal, oriented, first, restarts, max_iter, rng_seed, timeout, near)

    def _judged(self, q: np.ndarray, goal: pin.SE3, oriented: bool) -> IKSolution:
        """``q`` measured by the URDF's mimic model: errors to ``goal`` and every joint's limits.

        Args:
            q: The independent joints' values [rad] or [m].
            goal: Target ``T_base_tip`` [m].
            oriented: Whether the goal's rotation counts (else the rotation error is None).
        """
        pose = self.frame_pose(q, "tool")
        position = float(np.linalg.norm(pose.translation - goal.translation))
        rotation = (
            rotation_error(pose.rotation.ravel().tolist(), goal.rotation.ravel().tolist())
            if oriented
            else None
        )
        return IKSolution(q.copy(), "", self.within_limits(q), position, rotation)

    def _vector(self, q: npt.ArrayLike) -> np.ndarray:
        """``q`` as a float vector of the independent joints, else :class:`JointVectorError`."""
        try:
            array = np.array(q, dtype=float)
        except (TypeError, ValueError) as err:
            raise JointVectorError(f"joint values must be numbers, got {q!r}", self.nq, -1) from err
        if array.shape != (self.nq,) or not np.isfinite(array).all():
            raise JointVectorError(
                f"'{self.chain.name}' has {self.nq} independent joints "
                f"({', '.join(self.joint_names)}): give {self.nq} finite values, got {array.tolist()}",
                self.nq,
                array.size,
            )
        return array


def _narrowed_limits(chain: UrdfChain) -> tuple[np.ndarray, np.ndarray]:
    """The independent joints' limits, narrowed so that every mimic joint stays in its own."""
    index = {joint.name: i for i, joint in enumerate(chain.independent)}
    lower = np.array([joint.lower for joint in chain.independent])
    upper = np.array([joint.upper for joint in chain.independent])
    for joint in chain.joints:
        if joint.mimic is None or joint.continuous or joint.mimic.multiplier == 0.0:
            continue
        bounds = sorted(
            (value - joint.mimic.offset) / joint.mimic.multiplier
            for value in (joint.lower, joint.upper)
        )
        i = index[joint.mimic.leader]
        lower[i], upper[i] = max(lower[i], bounds[0]), min(upper[i], bounds[1])
    return lower, upper


def load_mimic_arm(path: str | Path, base: str | None = None, tip: str | None = None) -> MimicArm:
    """The chain from ``base`` to ``tip`` of a URDF, mimic joints followed.

    Args:
        path: A URDF file (any suffix; ``.xacro`` with xacrodoc).
        base: Base link (default: the root link).
        tip: Tip link (default: the single leaf below the last moving joint).

    Raises:
        dh2urdf.urdf_chain.UrdfChainError: No serial chain from base to tip (see
            :func:`dh2urdf.urdf_chain.read_chain`).
        ModelLoadError: The mimic joints' limits leave no joint vector.
    """
    from dh2urdf.urdf_chain import read_chain

    return mimic_arm_from_chain(read_chain(path, base, tip))


def mimic_arm_from_chain(chain: UrdfChain) -> MimicArm:
    """The :class:`MimicArm` of a chain read by :func:`dh2urdf.urdf_chain.read_chain`.

    Raises:
        dh2urdf.urdf_chain.UrdfChainError: The DH table does not reproduce the chain.
        ModelLoadError: The mimic joints' limits leave no joint vector.
    """
    from dh2urdf.urdf_parse import build_pinocchio_model
    from dh2urdf.urdf_to_dh import check_table, table_from_chain

    table = table_from_chain(chain)
    check_table(chain, table)
    lower, upper = _narrowed_limits(chain)
    if not (lower <= upper).all():
        names = [n for n, lo, hi in zip(chain.independent, lower, upper, strict=True) if lo > hi]
        raise ModelLoadError(
            f"{chain.path}: the limits of the mimic joints leave joint {names[0].name!r} no value"
        )
    return MimicArm(
        chain=chain,
        table=table,
        robot=robot_from_table(table),
        reference=build_pinocchio_model(chain.text, chain.path, mimic=True),
        lower=lower,
        upper=upper,
    )


def load_arm(
    robot: str | Path, base: str | None = None, tip: str | None = None
) -> RobotModel | MimicArm:
    """:func:`~kin.robot_model.load_robot`, but a URDF chain with mimic joints: a :class:`MimicArm`.

    A mimic joint in series on the chain follows its leader (``q = multiplier * q_leader +
    offset``): the arm's joint vector holds the independent joints only
    (:func:`load_mimic_arm`). Every other robot loads as :func:`~kin.robot_model.load_robot`
    does.

    Raises:
        The errors of :func:`~kin.robot_model.load_robot` (but for the mimic refusal), and
        :func:`load_mimic_arm`'s.
    """
    path = urdf_file(robot)
    if path is None:
        return load_robot(robot, base, tip)
    from dh2urdf.urdf_chain import read_chain

    chain = read_chain(path, base, tip)
    if all(joint.mimic is None for joint in chain.joints):
        return robot_from_chain(chain)
    return mimic_arm_from_chain(chain)

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

Not yet wired to the ``kin`` commands (their joint units, seeds and closed forms read one
variable per table row): :func:`kin.load_robot` names this module for such a chain.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from dh2urdf import DHTable
from dh2urdf.urdf_chain import UrdfChain

from .exceptions import JointVectorError, ModelLoadError
from .ik.judge import POSITION_TOLERANCE, ROTATION_TOLERANCE, rotation_error
from .ik.result import IKSolution
from .robot_model import RobotModel

__all__ = ["MimicArm", "load_mimic_arm"]


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
        from dh2urdf.dh_table import dh_link_transform

        product = np.array(self.table.T_world_base)
        for row, value in zip(self.table.rows, self.chain.expand(self._vector(q)), strict=True):
            theta, d = row.dh_values(float(value))
            product = product @ dh_link_transform(self.table.convention, row.a, row.alpha, d, theta)
        return product @ self.table.T_last_tool

    def reference_fk(self, q: npt.ArrayLike) -> np.ndarray:
        """``T_base_tip`` (4x4, [m]) by Pinocchio's mimic model of the original URDF."""
        model = self.reference
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
        tip = model.getFrameId(self.chain.tip, pin.FrameType.BODY)
        return np.array((data.oMf[base].inverse() * data.oMf[tip]).homogeneous)

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
        target = pin.SE3(np.asarray(T_base_target, dtype=float))
        coupling = self.coupling
        model, data = self.robot.model, self.robot.model.createData()
        tool = model.getFrameId(self.robot.tool_frame)
        lower, upper = self.lower, self.upper
        middle = 0.5 * (lower + upper)
        rng = np.random.default_rng(rng_seed)
        starts = [middle if seed is None else np.clip(self._vector(seed), lower, upper)]
        starts += [rng.uniform(lower, upper) for _ in range(restarts)]
        for start in starts:
            q = start.copy()
            for _ in range(max_iter):
                full = self.chain.expand(q)
                pin.framesForwardKinematics(model, data, full)
                error = pin.log6(data.oMf[tool].actInv(target)).vector
                if float(np.linalg.norm(error)) < 1e-12:
                    break
                jacobian = pin.computeFrameJacobian(model, data, full, tool, pin.LOCAL) @ coupling
                step = np.linalg.lstsq(
                    jacobian.T @ jacobian + 1e-10 * np.eye(self.nq), jacobian.T @ error, rcond=None
                )[0]
                q = np.clip(q + step, lower, upper)
            answer = self._judged(q, target)
            if answer is not None:
                return answer
        return None

    def _judged(self, q: np.ndarray, target: pin.SE3) -> IKSolution | None:
        """``q`` as a solution when the URDF's mimic model puts it on target inside the limits."""
        pose = self.reference_fk(q)
        position = float(np.linalg.norm(pose[:3, 3] - target.translation))
        rotation = rotation_error(pose[:3, :3].ravel().tolist(), target.rotation.ravel().tolist())
        on_target = position < POSITION_TOLERANCE and rotation < ROTATION_TOLERANCE
        if not (on_target and self.within_limits(q)):
            return None
        return IKSolution(q.copy(), "", True, position, rotation)

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
    from dh2urdf.urdf_parse import build_pinocchio_model
    from dh2urdf.urdf_to_dh import check_table, table_from_chain

    from .robot_model import robot_from_table

    chain = read_chain(path, base, tip)
    table = table_from_chain(chain)
    check_table(chain, table)
    lower, upper = _narrowed_limits(chain)
    if not (lower <= upper).all():
        names = [n for n, lo, hi in zip(chain.independent, lower, upper, strict=True) if lo > hi]
        raise ModelLoadError(
            f"{path}: the limits of the mimic joints leave joint {names[0].name!r} no value"
        )
    return MimicArm(
        chain=chain,
        table=table,
        robot=robot_from_table(table),
        reference=build_pinocchio_model(chain.text, chain.path, mimic=True),
        lower=lower,
        upper=upper,
    )

"""Random general 6R and 7R arms for the closed-form tests, and the 6R Jacobian's smallest singular
value by central differences of the reference FK (no kin code).
"""

from __future__ import annotations

import math

import numpy as np

from dh2urdf import DHTable
from support.arm_tables import make_table, random_pose
from support.dh_reference import ReferenceTable, fk_frames

PI = math.pi


#: Below this smallest singular value of the 6x6 Jacobian a pose counts as near-singular.
NEAR_SINGULAR = 1e-5


def random_arm(
    seed: int, convention: str, joints: int = 6, reach: float = 0.5, name: str | None = None
) -> tuple[DHTable, ReferenceTable]:
    """A random revolute table of ``joints`` rows (lengths +-``reach`` [m], any twist and offset,
    random base and tool, limits +-2 pi) and the same numbers as the reference's arrays."""
    rng = np.random.default_rng(seed)
    a, d = rng.uniform(-reach, reach, (2, joints))
    alpha, theta = rng.uniform(-PI, PI, (2, joints))
    base, tool = random_pose(rng), random_pose(rng)
    name = f"random{seed}" if name is None else name
    table = make_table(a, alpha, d, theta, convention, base, tool, name=name)
    ones = np.ones(joints)
    reference = ReferenceTable(
        convention, tuple(f"j{i}" for i in range(1, joints + 1)), np.zeros(joints, dtype=bool),
        a, alpha, d, theta, -2 * PI * ones, 2 * PI * ones, base, tool,
    )  # fmt: skip
    return table, reference


def random_7r_arm(seed: int, convention: str) -> tuple[DHTable, ReferenceTable]:
    """A random 7R arm (lengths +-0.4 m) for the 7R closed forms, as :func:`random_arm`."""
    return random_arm(seed, convention, 7, 0.4, f"r7_{convention}{seed}")


def sigma_min(reference: ReferenceTable, q: np.ndarray, step: float = 1e-6) -> float:
    """Smallest singular value of the tool's 6x6 Jacobian at ``q`` (central differences)."""
    columns = []
    for j in range(6):
        dq = np.zeros(6)
        dq[j] = step
        plus, minus = reference_tool(reference, np.stack((q + dq, q - dq)))
        dp = (plus[:3, 3] - minus[:3, 3]) / (2 * step)
        dR = (plus[:3, :3] - minus[:3, :3]) / (2 * step) @ plus[:3, :3].T
        columns.append(np.concatenate((dp, [dR[2, 1], dR[0, 2], dR[1, 0]])))
    return float(np.linalg.svd(np.stack(columns, axis=1), compute_uv=False).min())


def reference_tool(reference: ReferenceTable, q: np.ndarray) -> np.ndarray:
    """Tool poses (N, 4, 4) of joint vectors (N, 6) [rad] by the plain DH product."""
    return fk_frames(reference, q)[:, -1]

"""The spurious roots ``x = +-i`` of the general 6R elimination, deflated once per arm.

With the half-angle tangent ``x`` of the eliminated joint, ``(1 + x^2) (1, sin, cos)`` vanishes
to ``(0, +-i, 1)`` at ``x = +-i``: the rotating rows of the left side's coefficients
``P(x) = P0 + P1 x + P2 x^2`` (:mod:`._general_6r_elimination`) become dependent there, and
``P(i)`` (14 x 9) has rank 4 whatever the pose (the pose enters through ``Q``'s column 0 with a
factor ``1 + x^2``, and through a left multiplication). So the null space of the 12 x 12
``M(i)`` holds the arm-constant space ``V`` (4 dimensions: ``v[:9]`` and ``v[3:]`` in the null
space of ``P(i)``), and the 24 x 24 companion matrix has the invariant subspace spanned by the
real and imaginary parts of ``(v, x v)`` (8 dimensions): its 8 spurious eigenvalues. An
orthonormal basis ``Q2`` (24 x 16) of its complement, made here once, leaves the 16 others as
the eigenvalues of ``Q2^T A Q2``, which ``kin/_native/ik/analytic/six_r/_general6r.c`` hands LAPACK instead of
``A`` (about a third of the work).
"""

from __future__ import annotations

import numpy as np

#: A singular value of ``P(i)`` below this times the largest counts as zero; the deflation is
#: only made when the spectrum has a clear gap (rank 4 and the 4th above :data:`GAP`).
ZERO = 1e-12
GAP = 1e-8


def deflation(P: np.ndarray) -> tuple[int, np.ndarray]:
    """The companion matrices' deflating bases of an arm's left side ``P`` (3, 14, 9).

    Returns:
        ``m`` (16, or 24 when the arm gives no clean rank-4 ``P(i)``: no deflation) and the
        bases (2, 24, 24): ``[0]`` for the companion on ``M2`` (eigenvalue ``x``), ``[1]`` on
        ``M0`` (eigenvalue ``1/x``); the first ``m`` columns of each are orthonormal and span
        the complement of the spurious eigenvectors.
    """
    eye = np.stack((np.eye(24), np.eye(24)))
    _, s, vh = np.linalg.svd(P[0] + 1j * P[1] - P[2])
    rank = int((s > ZERO * s[0]).sum())
    if rank != 4 or s[3] < GAP * s[0]:
        return 24, eye
    rows = vh[:rank]  # v[:9] and v[3:] orthogonal to them
    A = np.zeros((2 * rank, 12), dtype=complex)
    A[:rank, :9], A[rank:, 3:] = rows, rows
    _, s2, vh2 = np.linalg.svd(A)
    V = vh2[int((s2 > ZERO * s2[0]).sum()) :].conj().T  # (12, d)
    if V.shape[1] != 4:
        return 24, eye
    bases = np.empty((2, 24, 24))
    for k, x in enumerate((1j, -1j)):  # x = i on M2; 1/x = -i on M0
        w = np.concatenate((V, x * V))  # eigenvectors (v, x v)
        Q = np.linalg.qr(np.concatenate((w.real, w.imag), axis=1), mode="complete")[0]
        bases[k] = np.concatenate((Q[:, 8:], Q[:, :8]), axis=1)  # the complement first
    return 16, bases

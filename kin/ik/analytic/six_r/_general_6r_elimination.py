"""Raghavan-Roth elimination of a general 6R loop: the 12x12 quadratic eigenproblem and its roots.

References: M. Raghavan and B. Roth, "Inverse kinematics of the general 6R manipulator and
related linkages", ASME J. Mech. Des. 115(3):502-508, 1993; D. Manocha and J. F. Canny,
"Efficient inverse kinematics for general 6R manipulators", IEEE Trans. Robot. Autom.
10(5):648-657, 1994.

The arm is a chain ``T(q) = F0 Rz(q1) F1 Rz(q2) F2 ... Rz(q6) F6`` of constant rigid transforms
``F_i`` (4x4, [m]). A tool pose ``T`` closes it into the loop ``Rz(u1) C1 Rz(u2) C2 ... Rz(u6) C6
= I``: read forwards ``u_k = q_k``, ``C_k = F_k`` (k < 6) and ``C6 = F6 T^-1 F0``; read
backwards ``u_k = -q_(7-k)``, ``C_k = F_(6-k)^-1`` and ``C6 = F0^-1 T F6^-1``.

A :class:`Formulation` (a reading and a start ``a``) writes the loop as

    ``Rz(u_a) C_a Rz(u_a+1) C_a+1 Rz(u_a+2) . C_a+2 (z, o)
    = C_a+5^-1 Rz(-u_a+5) C_a+4^-1 Rz(-u_a+4) . C_a+3^-1 (z, o)``

(indices modulo 6): the axis ``l`` and the point ``p`` that both sides map the unit z axis and
the origin to (``u_a+3`` drops out). From ``l`` and ``p`` the 14 Raghavan-Roth equations are
``l, p, p.p, p.l, p x l, (p.p) l - 2 (p.l) p``; each side is then linear in the products of
``{1, sin, cos}`` of its joints, so ``P(u_a) m(u_a+1, u_a+2) = Q m'(u_a+4, u_a+5)`` with
``P`` linear in ``(1, sin u_a, cos u_a)`` (14 x 9) and ``Q`` constant per pose (14 x 9). The
coefficients are read exactly by sampling each side on a 3-point grid per joint (the basis
``{1, sin, cos}`` at 0, 120 and 240 deg is invertible) instead of by symbolic expansion.

The 8 non-constant columns of ``Q`` are eliminated with the left null space of ``Q`` (6 rows
from its SVD): 6 equations in the 9 products of ``u_a+1, u_a+2``. With half-angle tangents
``x, y, z`` of ``u_a - tau_x``, ``u_a+1 - tau_y``, ``u_a+2 - tau_z`` (fixed shifts ``tau``,
away from the angles arms are often at) they are biquadratic in ``y, z`` and quadratic in ``x``;
with the same equations times ``y`` they are 12 equations linear in the 12 monomials
``y^i z^j`` (``i <= 3``, ``j <= 2``): ``(M2 x^2 + M1 x + M0) v = 0``, solved as a 24x24
companion eigenproblem (in ``x`` or in ``1/x``, whichever leading matrix is better conditioned).
Its real eigenvalues give ``u_a``, the eigenvectors ``u_a+1``, ``u_a+2``; the monomials of
``u_a+4``, ``u_a+5`` then follow by least squares on ``Q``, ``u_a+3`` from the loop. Up to 16
real roots exist; 8 of the 24 eigenvalues are the spurious pairs ``x = +-i``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._stacked_transforms import inverse, rot_z, rz_times, times, times_rz

#: Sample angles of the coefficient fits [rad], and ``{1, sin, cos}`` at them (3x3).
_GRID = np.array([0.0, 2.0 * math.pi / 3.0, 4.0 * math.pi / 3.0])
_BASIS = np.stack([np.ones(3), np.sin(_GRID), np.cos(_GRID)], axis=1)
_FIT9 = np.linalg.inv(np.kron(_BASIS, _BASIS))
_FIT27 = np.linalg.inv(np.kron(np.kron(_BASIS, _BASIS), _BASIS))
#: ``Rz(-u)`` at the 9 grid points of the right side: ``u_a+4`` slow, ``u_a+5`` fast.
_ROT4 = np.zeros((9, 4, 4))
_ROT5 = np.zeros((9, 4, 4))
for _rot, _angles in ((_ROT4, -np.repeat(_GRID, 3)), (_ROT5, -np.tile(_GRID, 3))):
    _rot[:, 0, 0] = _rot[:, 1, 1] = np.cos(_angles)
    _rot[:, 1, 0] = np.sin(_angles)
    _rot[:, 0, 1] = -np.sin(_angles)
    _rot[:, 2, 2] = _rot[:, 3, 3] = 1.0
#: Shifts of the half-angle tangents (x, y, z) [rad]: a root at ``tau + pi`` is at infinity.
TAU = (0.4137, -0.7219, 1.1113)
#: An eigenvalue is taken as real when ``|Im| <= IMAG_TOL (1 + |lambda|)`` (Newton decides).
IMAG_TOL = 1e-3


def equations(axis: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The 14 Raghavan-Roth quantities (..., 14) of axes ``l`` and points ``p`` (..., 3) [m]."""
    out = np.empty(p.shape[:-1] + (14,))
    pp = np.einsum("...i,...i->...", p, p, out=out[..., 6])[..., None]
    pl = np.einsum("...i,...i->...", p, axis, out=out[..., 7])[..., None]
    out[..., :3] = axis
    out[..., 3:6] = p
    _cross(p, axis, out[..., 8:11])
    out[..., 11:] = pp * axis - 2.0 * pl * p
    return out


def _cross(a: np.ndarray, b: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """Cross products of (..., 3) vectors (faster than ``np.cross`` on small stacks), into ``out``."""
    if out is None:
        out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def _half_angle(tau: float) -> np.ndarray:
    """``H`` with ``(1 + t^2) (1, sin u, cos u) = H (1, t, t^2)`` for ``t = tan((u - tau)/2)``."""
    s, c = math.sin(tau), math.cos(tau)
    return np.array([[1.0, 0.0, 1.0], [s, 2.0 * c, -s], [c, -2.0 * s, -c]])


@dataclass(frozen=True, eq=False)
class Formulation:
    """One way of eliminating a 6R loop (see the module): its reading, start and fixed parts.

    Attributes:
        reverse: The loop read from the tool (joints ``-q6 .. -q1``).
        start: The first joint ``a`` (0, 1 or 2, 0-based) of the three kept; ``u_a`` is the
            eigenvalue.
        F: The chain's constant transforms ``F0 .. F6`` (7, 4, 4) [m].
    """

    reverse: bool
    start: int
    F: np.ndarray = field(repr=False)
    joints: tuple[int, ...] = field(init=False)
    signs: tuple[float, ...] = field(init=False)
    _C: list[np.ndarray | None] = field(init=False, repr=False)
    _C_inv: list[np.ndarray] = field(init=False, repr=False)
    _C_fixed: list[np.ndarray] = field(init=False, repr=False)
    _C_one: list[np.ndarray] = field(init=False, repr=False)
    _C_inv_one: list[np.ndarray] = field(init=False, repr=False)
    _h0: np.ndarray = field(init=False, repr=False)
    _P: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        F = self.F
        if self.reverse:
            joints = tuple(5 - k for k in range(6))
            signs = (-1.0,) * 6
            C: list[np.ndarray | None] = [inverse(F[5 - k]) for k in range(5)] + [None]
        else:
            joints, signs = tuple(range(6)), (1.0,) * 6
            C = [F[k + 1] for k in range(5)] + [None]
        setattr_ = object.__setattr__
        setattr_(self, "joints", joints)
        setattr_(self, "signs", signs)
        setattr_(self, "_C", C)
        setattr_(self, "_C_inv", [inverse(c) for c in C[:5] if c is not None])
        setattr_(self, "_C_fixed", [c for c in C[:5] if c is not None])
        setattr_(self, "_C_one", [c[None] for c in self._C_fixed])
        setattr_(self, "_C_inv_one", [c[None] for c in self._C_inv])
        a = self.start
        # Left side at the 27 grid points (u_a, u_a+1, u_a+2), fitted on {1, s, c}^3.
        g = np.stack(np.meshgrid(_GRID, _GRID, _GRID, indexing="ij"), axis=-1).reshape(27, 3)
        X = rot_z(g[:, 0]) @ C[a] @ rot_z(g[:, 1]) @ C[a + 1] @ rot_z(g[:, 2]) @ C[a + 2]
        values = equations(X[:, :3, 2], X[:, :3, 3])  # (27, 14)
        coeff = (_FIT27 @ values).reshape(3, 9, 14)  # (theta basis, phi-psi basis, eq)
        h = np.kron(_half_angle(TAU[1]), _half_angle(TAU[2]))  # (9 basis, 9 monomials)
        P1, Ps, Pc = (coeff[k].T @ h for k in range(3))  # (14, 9) each, in y^i z^j
        s, c = math.sin(TAU[0]), math.cos(TAU[0])
        setattr_(
            self,
            "_P",
            np.stack((P1 + s * Ps + c * Pc, 2.0 * c * Ps - 2.0 * s * Pc, P1 - s * Ps - c * Pc)),
        )
        setattr_(self, "_h0", np.kron(np.array([1.0, 0.0, 1.0]), np.array([1.0, 0.0, 1.0])))

    def twin_block(self) -> np.ndarray:
        """The arm's float64 block of ``kin/_native/ik/analytic/six_r/_general6r.c`` (its ``ARM_*`` layout).

        Start, reading, the fixed ``C_k`` and their inverses, the left side's coefficients, the
        chain ``F0 .. F6`` [m] and ``F0^-1``, ``F6^-1``, the fit on the grid, :data:`TAU` and the
        deflation of the spurious roots (:mod:`._general_6r_deflation`).
        """
        from ._general_6r_deflation import deflation

        kept, bases = deflation(self._P)
        parts = (
            [float(self.start), float(self.reverse)],
            self._C_fixed,
            self._C_inv,
            self._P,
            self.F,
            inverse(self.F[0]),
            inverse(self.F[6]),
            _FIT9,
            TAU,
            [float(kept)],
            bases,
        )
        return np.concatenate([np.ravel(np.asarray(part, dtype=float)) for part in parts])

    def _loop_constants(self, K: np.ndarray) -> tuple[list[np.ndarray], list[np.ndarray]]:
        """``C1 .. C6`` of N poses and their inverses, (N, 4, 4) each (see the module).

        The fixed ones are (1, 4, 4) (they broadcast: a stack of N views of one matrix made
        NumPy's matmul about five times slower); ``C6`` is ``K^-1`` read forwards, ``K``
        backwards.
        """
        K_inv = inverse(K)
        G, G_inv = (K, K_inv) if self.reverse else (K_inv, K)
        return self._C_one + [G], self._C_inv_one + [G_inv]

    def candidates(self, K: np.ndarray, careful: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Joint vectors ``q`` [rad] of the real eigenvalues of N poses.

        Args:
            K: ``F0^-1 T F6^-1`` of the N tool poses ``T`` (N, 4, 4) [m].
            careful: Also read every solution of a multiple root (solutions sharing ``u_a``):
                its null space of ``M(x)`` by the shift in ``y`` (:func:`_multiple_root`).

        Returns:
            ``q`` (N, B, 6) [rad] of the (near-)real eigenvalues first (B: the most of a pose;
            a pose's other rows are non-real, anything, or NaN) and the imaginary parts (N, B)
            of the eigenvalues, relative to ``1 + |lambda|``.
        """
        n = K.shape[0]
        C, C_inv = self._loop_constants(K)
        a = self.start
        i3, i4, i5 = (a + 3) % 6, (a + 4) % 6, (a + 5) % 6
        # Right side at the 9 grid points (u_a+4, u_a+5), fitted on {1, s, c}^2.
        Y = (
            C_inv[i5][:, None] @ _ROT5[None] @ C_inv[i4][:, None] @ _ROT4[None] @ C_inv[i3][:, None]
        )  # (N, 9, 4, 4)
        values = equations(Y[..., :3, 2], Y[..., :3, 3])  # (N, 9, 14)
        Q = np.einsum("ij,njk->nki", _FIT9, values)  # (N, 14, 9)
        q0 = Q[:, :, 0]
        P = self._P[None] - np.stack((q0, np.zeros_like(q0), q0), axis=1)[..., None] * self._h0
        U, sv, Vt = np.linalg.svd(Q[:, :, 1:], full_matrices=True)
        null = np.swapaxes(U[:, :, 8:], 1, 2)  # (N, 6, 14)
        S = null[:, None] @ P  # (N, 3, 6, 9)
        M = np.zeros((n, 3, 12, 12))
        M[:, :, :6, :9] = S
        M[:, :, 6:, 3:] = S
        values, flip, vectors = _quadratic_eig(M)  # (N, 24), (N,), (N, 24, 24)
        imag = np.abs(values.imag) / (1.0 + np.abs(values))
        # Only the (near-)real roots go on: each pose's first, as many columns as the most real.
        real = imag <= IMAG_TOL
        b = max(int(real.sum(axis=1).max(initial=0)), 1)
        order = np.argsort(~real, axis=1, kind="stable")[:, :b]
        rows = np.arange(n)[:, None]
        values, imag = values[rows, order], imag[rows, order]
        vectors = _half(vectors[rows, order])  # (N, B, 12)
        # x = tan((u_a - tau) / 2) is the eigenvalue, or its inverse when flipped.
        num = np.where(flip[:, None], 1.0, values.real)
        den = np.where(flip[:, None], values.real, 1.0)
        theta = TAU[0] + 2.0 * np.arctan2(num, den)
        V = _real_vectors(vectors).reshape(n, b, 4, 3)
        phi = TAU[1] + 2.0 * _ratio_angle(V, axis=2)
        psi = TAU[2] + 2.0 * _ratio_angle(V, axis=3)
        if careful:
            theta, phi, psi, imag = _multiple_roots(M, values, flip, theta, phi, psi, imag)
            b = theta.shape[1]
        # Right-side joints from the monomials: Q' m' = f_L - Q0.
        u = np.full((n, b, 6), np.nan)
        u[:, :, a], u[:, :, (a + 1) % 6], u[:, :, (a + 2) % 6] = theta, phi, psi
        fixed = self._C_fixed
        L = times(
            times_rz(times(times_rz(rz_times(theta, fixed[a]), phi), fixed[a + 1]), psi),
            fixed[a + 2],
        )  # (N, B, 4, 4)
        f = equations(L[..., :3, 2], L[..., :3, 3]) - q0[:, None]  # (N, 24, 14)
        inv_s = np.where(sv > sv[:, :1] * 1e-12, 1.0 / np.where(sv > 0, sv, 1.0), 0.0)
        pinv = np.swapaxes(Vt, 1, 2) @ (inv_s[..., None] * np.swapaxes(U[:, :, :8], 1, 2))
        m = np.einsum("nij,nbj->nbi", pinv, f)  # (N, 24, 8): (i4, i5) index - 1
        u[:, :, i5] = np.arctan2(m[..., 0], m[..., 1])
        u[:, :, i4] = np.arctan2(m[..., 2], m[..., 5])
        R = times_rz(C[i3][:, None], u[:, :, i4]) @ C[i4][:, None]
        R = times_rz(R, u[:, :, i5]) @ C[i5][:, None]
        Rz3 = np.swapaxes(L[..., :3, :3], -1, -2) @ np.swapaxes(R[..., :3, :3], -1, -2)
        u[:, :, i3] = np.arctan2(Rz3[..., 1, 0] - Rz3[..., 0, 1], Rz3[..., 0, 0] + Rz3[..., 1, 1])
        q = np.empty_like(u)
        for k, (j, sign) in enumerate(zip(self.joints, self.signs)):
            q[..., j] = sign * u[..., k]
        return q, imag


def _multiple_roots(
    M: np.ndarray,
    values: np.ndarray,
    flip: np.ndarray,
    theta: np.ndarray,
    phi: np.ndarray,
    psi: np.ndarray,
    imag: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``theta, phi, psi, imag`` (N, B) with the solutions of multiple real roots appended.

    At a root shared by k solutions the null space of ``M(x)`` has k dimensions and an
    eigenvector mixes them. The true vectors ``v = y^i z^j`` (4 x 3) are ``N c`` for the null
    basis ``N``; the rows ``i = 1..3`` are ``y`` times the rows ``i = 0..2``, so ``y`` and ``c``
    are the eigenpairs of ``down^+ up`` (k x k), each giving ``phi`` and ``psi``.
    """
    n = M.shape[0]
    pose, root = np.nonzero(imag <= IMAG_TOL)
    if not pose.size:
        return theta, phi, psi, imag
    x = values.real[pose, root]
    f = flip[pose][:, None, None]
    xx = x[:, None, None]
    Mp = M[pose]
    A = np.where(
        f,
        Mp[:, 0] * xx * xx + Mp[:, 1] * xx + Mp[:, 2],
        Mp[:, 2] * xx * xx + Mp[:, 1] * xx + Mp[:, 0],
    )
    _, sv, vh = np.linalg.svd(A)
    k = np.minimum((sv < 1e-7 * sv[:, :1]).sum(axis=1), 4)
    extra: list[list[tuple[float, float, float]]] = [[] for _ in range(n)]
    for r in np.nonzero(k >= 2)[0]:
        basis = vh[r, -k[r] :].T.reshape(4, 3, k[r])
        down, up = basis[:3].reshape(9, -1), basis[1:].reshape(9, -1)
        shift = np.linalg.lstsq(down, up, rcond=None)[0]
        ys, cs = np.linalg.eig(shift)
        for j in range(len(ys)):
            if abs(ys[j].imag) > IMAG_TOL * (1.0 + abs(ys[j])):
                continue
            v = _real_vectors((basis.reshape(12, -1) @ cs[:, j])[None])[0].reshape(1, 1, 4, 3)
            extra[pose[r]].append(
                (
                    float(theta[pose[r], root[r]]),
                    float(TAU[1] + 2.0 * _ratio_angle(v, axis=2)[0, 0]),
                    float(TAU[2] + 2.0 * _ratio_angle(v, axis=3)[0, 0]),
                )
            )
    width = max(len(rows) for rows in extra)
    if not width:
        return theta, phi, psi, imag
    more = np.full((n, width, 3), np.nan)
    for i, rows in enumerate(extra):
        if rows:
            more[i, : len(rows)] = rows
    zeros = np.where(np.isnan(more[..., 0]), np.inf, 0.0)
    return (
        np.concatenate((theta, more[..., 0]), axis=1),
        np.concatenate((phi, more[..., 1]), axis=1),
        np.concatenate((psi, more[..., 2]), axis=1),
        np.concatenate((imag, zeros), axis=1),
    )


def _quadratic_eig(M: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eigenpairs of ``(M2 x^2 + M1 x + M0) v = 0`` for N stacks ``M`` (N, 3, 12, 12).

    Per pose the companion matrix is built on ``M2`` (eigenvalues ``x``) or, when ``M0`` is
    better conditioned (``flip``), on ``M0`` (eigenvalues ``1/x``). Returns the 24 complex
    eigenvalues (N, 24), ``flip`` (N,) and the companion matrix's eigenvectors ``(v, x v)``
    (N, 24, 24) (:func:`_half` reads ``v``).
    """
    n = M.shape[0]
    M0, M1, M2 = M[:, 0], M[:, 1], M[:, 2]
    # |det| over the product of the row norms (Hadamard's ratio, 1 for orthogonal rows): the
    # leading matrix farther from singular of the two.
    leads = M[:, ::-2]  # M2, M0
    sign, logdet = np.linalg.slogdet(leads)
    norms = np.log(np.maximum(np.linalg.norm(leads, axis=3), 1e-300)).sum(axis=2)
    ratio = np.where(sign != 0.0, logdet - norms, -np.inf)  # (N, 2)
    flip = ratio[:, 1] > ratio[:, 0]
    lead = np.where(flip[:, None, None], M0, M2)
    tail = np.where(flip[:, None, None], M2, M0)
    A = np.zeros((n, 24, 24))
    A[:, :12, 12:] = _EYE12
    rhs = np.concatenate((tail, M1), axis=2)
    try:
        A[:, 12:, :] = -np.linalg.solve(lead, rhs)
    except np.linalg.LinAlgError:
        A[:, 12:, :] = -np.linalg.pinv(lead) @ rhs
    # A degenerate table (lengths of 1e-300 m, ...) can overflow a pose's companion matrix: that
    # pose gets NaN eigenpairs (no candidates) instead of stopping every pose.
    finite = np.isfinite(A).all(axis=(1, 2))
    if finite.all():
        values, vectors = np.linalg.eig(A)  # (N, 24), (N, 24, 24): columns
    else:
        values = np.full((n, 24), np.nan, dtype=complex)
        vectors = np.full((n, 24, 24), np.nan, dtype=complex)
        if finite.any():
            values[finite], vectors[finite] = np.linalg.eig(A[finite])
    return values, flip, np.swapaxes(vectors, 1, 2)


def _half(vectors: np.ndarray) -> np.ndarray:
    """``v`` (..., 12) of companion eigenvectors ``(v, x v)`` (..., 24): the larger half."""
    top, bottom = vectors[..., :12], vectors[..., 12:]
    use_top = np.linalg.norm(top, axis=-1) >= np.linalg.norm(bottom, axis=-1)
    return np.where(use_top[..., None], top, bottom)


_EYE12 = np.eye(12)


def _real_vectors(v: np.ndarray) -> np.ndarray:
    """Complex vectors (..., 12) rotated so their largest entry is real, real part kept."""
    flat = v.reshape(-1, v.shape[-1])
    big = flat[np.arange(flat.shape[0]), np.argmax(np.abs(flat), axis=-1)].reshape(v.shape[:-1])
    phase = np.conj(big) / np.maximum(np.abs(big), 1e-300)
    return (v * phase[..., None]).real


def _ratio_angle(V: np.ndarray, axis: int) -> np.ndarray:
    """``atan`` of the ratio ``y`` (axis 2, of 4 entries) or ``z`` (axis 3, 3 entries) [rad].

    ``V`` (N, B, 4, 3) holds ``y^i z^j`` times a scale; the pair of consecutive entries with
    the largest norm gives ``atan2(next, this)``.
    """
    if axis == 2:
        this, nxt = V[:, :, :-1, :], V[:, :, 1:, :]
    else:
        this, nxt = V[:, :, :, :-1], V[:, :, :, 1:]
    n, b = V.shape[:2]
    this, nxt = this.reshape(n * b, -1), nxt.reshape(n * b, -1)
    rows, k = np.arange(n * b), np.argmax(this * this + nxt * nxt, axis=-1)
    return np.arctan2(nxt[rows, k], this[rows, k]).reshape(n, b)

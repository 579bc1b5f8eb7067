/*
 * Compiled twin of the first pass of the general 6R closed form (optional: without it the NumPy
 * path runs alone). kin/ik/analytic/six_r/_general_6r_elimination.py (Formulation.candidates,
 * careful=False) and general_6r.py (polish, distinct) are the reference; this file repeats them
 * operation for operation for one formulation and N poses, and tests/native/test_general6r_twin.py holds
 * the two to the same branches.
 *
 * Per pose: the right side of the loop at its 9 grid points -> Q (14x9); the left null space of
 * Q's last 8 columns (a Householder QR in C; LAPACK dgesvd where it is near rank-deficient) ->
 * the 12x12 matrix quadratic M2 x^2 + M1 x + M0; its 24x24 companion matrix on the better
 * conditioned leading matrix (a 12x12 LU in C: lu12; dgesv) -> its eigenvalues (dgeev's
 * steps), each (near-)real root's vector by inverse iteration on the 12x12 quadratic (the NumPy
 * path takes the companion's eigenvectors: the same line for a simple root) -> the joints,
 * Newton-polished on the true chain, kept on target, duplicates merged, ordered by joint 1.
 * LAPACK comes from SciPy's cython_lapack capsules at import (no link-time dependency).
 *
 * first_pass(arm, T, out, roots[, targets]): arm the float64 block of Formulation.twin_block
 * (layout in ARM_* below), T (N, 4, 4) the tool poses [m], out (N, 16, 6) the DH joint variables
 * [rad] (NaN rows after the branches), roots (N,) the real roots counted per pose, or -1 where
 * this pass cannot answer (a singular pencil, a singular leading matrix, a non-finite companion
 * matrix), or -2 where it is unclean (fewer branches than real roots, or odd) at a multiple root
 * (the NumPy path's careful pass reads those): the NumPy path answers that pose. targets
 * (N, 4, 4) [m], optional: the roots taken
 * at T (nearby poses) are polished onto these instead (general_6r.NUDGES).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

#include "_six_r_twin.h" /* check_branches_n: the 6R twins' verifier, here of 16 branches */
#undef BRANCHES          /* its 8 are the two families' */

typedef void dgeev_t(char *, char *, int *, double *, int *, double *, double *, double *, int *,
                     double *, int *, double *, int *, int *);
typedef void dgesvd_t(char *, char *, int *, int *, double *, int *, double *, double *, int *,
                      double *, int *, double *, int *, int *);
typedef void dgesv_t(int *, int *, double *, int *, int *, double *, int *, int *);
typedef void dgebal_t(char *, int *, double *, int *, int *, int *, double *, int *);
typedef void dgehd2_t(int *, int *, int *, double *, int *, double *, double *, int *);
typedef void dlahqr_t(int *, int *, int *, int *, int *, double *, int *, double *, double *, int *,
                      int *, double *, int *, int *);

static dgeev_t *dgeev_;
static dgesvd_t *dgesvd_;
static dgesv_t *dgesv_;
static dgebal_t *dgebal_;
static dgehd2_t *dgehd2_;
static dlahqr_t *dlahqr_;

/* The arm block: start, reverse, C_fixed (5 4x4), C_inv (5 4x4), P (3x14x9), F (7 4x4),
   F0^-1, F6^-1, FIT9 (9x9), TAU (3), m and the two deflating bases (2 24x24, row-major, the
   first m columns used; _general_6r_deflation.py). */
#define ARM_START 0
#define ARM_REVERSE 1
#define ARM_C 2
#define ARM_CINV (ARM_C + 80)
#define ARM_P (ARM_CINV + 80)
#define ARM_F (ARM_P + 378)
#define ARM_F0INV (ARM_F + 112)
#define ARM_F6INV (ARM_F0INV + 16)
#define ARM_FIT9 (ARM_F6INV + 16)
#define ARM_TAU (ARM_FIT9 + 81)
#define ARM_DEFLATED (ARM_TAU + 3)
#define ARM_BASES (ARM_DEFLATED + 1)
#define ARM_SIZE (ARM_BASES + 2 * 576)

#define BRANCHES 16
#define NEWTON_STEPS 8
#define NEWTON_TOL 1e-12
#define KEEP_TOL 1e-10
#define ROOT_TOL 1e-7
#define IMAG_TOL 1e-3
#define SAME_TOL 1e-6 /* kin.ik.result.SAME_BRANCH */

static const double GRID[3] = {0.0, 2.0 * M_PI / 3.0, 4.0 * M_PI / 3.0};

/* c = a b of 4x4 row-major transforms (c may not alias). */
static void mul4(const double *a, const double *b, double *c)
{
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            c[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j] +
                           a[4 * i + 3] * b[12 + j];
}

/* The first `rows` rows of x Rz into out, Rz's cosine c and sine s (it mixes columns 0 and 1). */
static void rz_rows(const double *x, double c, double s, double *out, int rows)
{
    for (int i = 0; i < rows; i++) {
        double x0 = x[4 * i], x1 = x[4 * i + 1];
        out[4 * i] = x0 * c + x1 * s;
        out[4 * i + 1] = x1 * c - x0 * s;
        out[4 * i + 2] = x[4 * i + 2];
        out[4 * i + 3] = x[4 * i + 3];
    }
}

/* x Rz(angle) into out. */
static void mul_rz(const double *x, double angle, double *out)
{
    rz_rows(x, cos(angle), sin(angle), out, 4);
}

static void rigid_inverse(const double *t, double *out)
{
    memset(out, 0, 16 * sizeof(double));
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) out[4 * i + j] = t[4 * j + i];
    for (int i = 0; i < 3; i++)
        out[4 * i + 3] = -(out[4 * i] * t[3] + out[4 * i + 1] * t[7] + out[4 * i + 2] * t[11]);
    out[15] = 1.0;
}

/* The 14 Raghavan-Roth quantities of the z axis and origin of transform t. */
static void equations(const double *t, double *out)
{
    double l[3] = {t[2], t[6], t[10]}, p[3] = {t[3], t[7], t[11]};
    double pp = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    double pl = p[0] * l[0] + p[1] * l[1] + p[2] * l[2];
    for (int k = 0; k < 3; k++) out[k] = l[k], out[3 + k] = p[k];
    out[6] = pp, out[7] = pl;
    out[8] = p[1] * l[2] - p[2] * l[1];
    out[9] = p[2] * l[0] - p[0] * l[2];
    out[10] = p[0] * l[1] - p[1] * l[0];
    for (int k = 0; k < 3; k++) out[11 + k] = pp * l[k] - 2.0 * pl * p[k];
}

/* Tool pose of DH variables u through the chain F (7 4x4, rigid: last rows 0 0 0 1), with the
   joints' axes and origins: mul_rz and mul4 on the top three rows only (the terms of the last
   row are exact zeros and ones: the same numbers, a quarter of the work saved). */
static void forward(const double *F, const double *u, double *T, double *axes, double *origins)
{
    double cur[12], t[12];
    memcpy(cur, F, sizeof cur);
    for (int i = 0; i < 6; i++) {
        axes[3 * i] = cur[2], axes[3 * i + 1] = cur[6], axes[3 * i + 2] = cur[10];
        origins[3 * i] = cur[3], origins[3 * i + 1] = cur[7], origins[3 * i + 2] = cur[11];
        const double *b = F + 16 * (i + 1);
        rz_rows(cur, cos(u[i]), sin(u[i]), t, 3);
        for (int r = 0; r < 3; r++) {
            const double *a = t + 4 * r;
            for (int j = 0; j < 3; j++) cur[4 * r + j] = a[0] * b[j] + a[1] * b[4 + j] + a[2] * b[8 + j];
            cur[4 * r + 3] = a[0] * b[3] + a[1] * b[7] + a[2] * b[11] + a[3];
        }
    }
    memcpy(T, cur, sizeof cur);
    T[12] = T[13] = T[14] = 0.0, T[15] = 1.0;
}

/* Error vector of pose T to target and its largest entry (inf beyond 90 deg of rotation). */
static double pose_error(const double *T, const double *target, double *e)
{
    double E[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            E[3 * i + j] = target[4 * i] * T[4 * j] + target[4 * i + 1] * T[4 * j + 1] +
                           target[4 * i + 2] * T[4 * j + 2];
    for (int k = 0; k < 3; k++) e[k] = target[4 * k + 3] - T[4 * k + 3];
    e[3] = 0.5 * (E[7] - E[5]);
    e[4] = 0.5 * (E[2] - E[6]);
    e[5] = 0.5 * (E[3] - E[1]);
    double size = 0.0;
    for (int k = 0; k < 6; k++) {
        double a = fabs(e[k]);
        if (a > size || isnan(a)) size = a;
    }
    return E[0] + E[4] + E[8] > 1.0 ? size : INFINITY;
}

/* Solve the n x n system a x = b (row-major, partial pivoting) in place: 0, or -1 if singular. */
static int solve_small(double *a, double *b, int n)
{
    for (int c = 0; c < n; c++) {
        int p = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(a[r * n + c]) > fabs(a[p * n + c])) p = r;
        if (a[p * n + c] == 0.0) return -1;
        if (p != c) {
            for (int k = 0; k < n; k++) {
                double t = a[c * n + k];
                a[c * n + k] = a[p * n + k], a[p * n + k] = t;
            }
            double t = b[c];
            b[c] = b[p], b[p] = t;
        }
        for (int r = c + 1; r < n; r++) {
            double f = a[r * n + c] / a[c * n + c];
            for (int k = c; k < n; k++) a[r * n + k] -= f * a[c * n + k];
            b[r] -= f * b[c];
        }
    }
    for (int c = n - 1; c >= 0; c--) {
        double s = b[c];
        for (int k = c + 1; k < n; k++) s -= a[c * n + k] * b[k];
        b[c] = s / a[c * n + c];
    }
    return 0;
}

/* Newton steps of u (6) onto target (general_6r.polish): the largest error left; u wrapped. */
static double polish(const double *F, double *u, const double *target)
{
    double T[16], axes[18], origins[18], e[6], error = INFINITY;
    for (int step = 0; step <= NEWTON_STEPS; step++) {
        forward(F, u, T, axes, origins);
        error = pose_error(T, target, e);
        if (step == NEWTON_STEPS || !(error > NEWTON_TOL && error < 1.0)) break;
        double J[36], JJt[36], y[6];
        for (int i = 0; i < 6; i++) {
            const double *z = axes + 3 * i;
            double r[3] = {T[3] - origins[3 * i], T[7] - origins[3 * i + 1],
                           T[11] - origins[3 * i + 2]};
            J[0 * 6 + i] = z[1] * r[2] - z[2] * r[1];
            J[1 * 6 + i] = z[2] * r[0] - z[0] * r[2];
            J[2 * 6 + i] = z[0] * r[1] - z[1] * r[0];
            J[3 * 6 + i] = z[0], J[4 * 6 + i] = z[1], J[5 * 6 + i] = z[2];
        }
        for (int i = 0; i < 6; i++) {
            for (int j = i; j < 6; j++) { /* symmetric: the lower triangle mirrored (same sums) */
                double s = 0.0;
                for (int k = 0; k < 6; k++) s += J[6 * i + k] * J[6 * j + k];
                JJt[6 * i + j] = JJt[6 * j + i] = s + (i == j ? 1e-14 : 0.0);
            }
            y[i] = e[i];
        }
        if (solve_small(JJt, y, 6) != 0) break;
        for (int i = 0; i < 6; i++) {
            double d = 0.0;
            for (int k = 0; k < 6; k++) d += J[6 * k + i] * y[k];
            u[i] += d > 0.5 ? 0.5 : (d < -0.5 ? -0.5 : d);
        }
    }
    for (int i = 0; i < 6; i++) {
        double w = fmod(u[i] + M_PI, 2.0 * M_PI);
        if (w < 0.0) w += 2.0 * M_PI;
        u[i] = w - M_PI;
    }
    return error;
}

static double wrap_gap(double d)
{
    double w = fmod(d + M_PI, 2.0 * M_PI);
    if (w < 0.0) w += 2.0 * M_PI;
    return w - M_PI;
}

/* general_6r.distinct of one pose: rows (m, 6) -> out (16, 6), NaN after the branches. */
static void distinct(double *rows, int m, double *out)
{
    double key[24];
    int order[24], n = 0;
    for (int r = 0; r < m; r++) key[r] = rows[6 * r] > M_PI - SAME_TOL ? rows[6 * r] - 2.0 * M_PI : rows[6 * r];
    for (int r = 0; r < m; r++) { /* stable insertion sort by key */
        int k = r;
        while (k > 0 && key[order[k - 1]] > key[r]) order[k] = order[k - 1], k--;
        order[k] = r;
    }
    for (int k = 0; k < BRANCHES * 6; k++) out[k] = NAN;
    int kept[24];
    for (int j = 0; j < m; j++) {
        const double *b = rows + 6 * order[j];
        int duplicate = 0;
        for (int i = j - 1; i >= 0 && !duplicate; i--) {
            const double *a = rows + 6 * order[i];
            if (!(fabs(wrap_gap(b[0] - a[0])) <= SAME_TOL)) continue;
            duplicate = 1;
            for (int k = 1; k < 6; k++)
                if (!(fabs(wrap_gap(b[k] - a[k])) <= SAME_TOL)) duplicate = 0;
        }
        if (!duplicate) kept[n++] = order[j];
    }
    for (int j = 0; j < n && j < BRANCHES; j++) memcpy(out + 6 * j, rows + 6 * kept[j], 6 * sizeof(double));
}

/* LU with partial pivoting of a 12x12 row-major matrix, in place (dgetf2's steps: the first
   largest entry of a column as pivot, row swaps in piv): a pivot below tiny set to +-tiny
   (tiny > 0), or an exact zero pivot left with its column not eliminated (tiny = 0). */
static void lu12(double *a, int *piv, double tiny)
{
    for (int c = 0; c < 12; c++) {
        int p = c;
        for (int r = c + 1; r < 12; r++)
            if (fabs(a[12 * r + c]) > fabs(a[12 * p + c])) p = r;
        piv[c] = p;
        if (p != c)
            for (int k = 0; k < 12; k++) {
                double t = a[12 * c + k];
                a[12 * c + k] = a[12 * p + k], a[12 * p + k] = t;
            }
        if (fabs(a[13 * c]) < tiny) a[13 * c] = a[13 * c] < 0.0 ? -tiny : tiny;
        if (a[13 * c] == 0.0) continue;
        for (int r = c + 1; r < 12; r++) {
            double f = a[12 * r + c] /= a[13 * c];
            for (int k = c + 1; k < 12; k++) a[12 * r + k] -= f * a[12 * c + k];
        }
    }
}

/* The transpose of a 12x12 row-major matrix (what LAPACK's column-major view of it sees). */
static void transpose12(const double *m, double *out)
{
    for (int i = 0; i < 12; i++)
        for (int j = 0; j < 12; j++) out[12 * j + i] = m[12 * i + j];
}

/* log |det| minus the log of the row norms of a 12x12 row-major matrix; -inf if singular. */
static double hadamard_ratio(const double *m)
{
    double a[144], norms = 0.0;
    int ipiv[12];
    for (int i = 0; i < 12; i++) {
        double s = 0.0;
        for (int j = 0; j < 12; j++) s += m[12 * i + j] * m[12 * i + j];
        norms += log(fmax(sqrt(s), 1e-300));
    }
    transpose12(m, a); /* the transpose's determinant is the same */
    lu12(a, ipiv, 0.0);
    double logdet = 0.0;
    for (int i = 0; i < 12; i++) {
        if (a[13 * i] == 0.0) return -INFINITY;
        logdet += log(fabs(a[13 * i]));
    }
    return logdet - norms;
}

/* atan2 of the consecutive pair (along y: step 3, 3x3 pairs; along z: step 1, 4x2) of largest norm. */
static double ratio_angle(const double *v, int along_y)
{
    double best = -1.0, angle = 0.0;
    for (int i = 0; i < (along_y ? 3 : 4); i++)
        for (int j = 0; j < (along_y ? 3 : 2); j++) {
            double t = v[3 * i + j], x = along_y ? v[3 * (i + 1) + j] : v[3 * i + j + 1];
            double size = t * t + x * x;
            if (size > best) best = size, angle = atan2(x, t);
        }
    return angle;
}

/* Whether M2 x^2 + M1 x + M0 (12x12 row-major) is singular at a generic x: its LU's smallest
   pivot below SINGULAR times the largest. */
#define SINGULAR 1e-11
static int singular_pencil(const double *m0, const double *m1, const double *m2)
{
    const double x = 0.3719; /* no arm's root in particular */
    double a[144];
    int ipiv[12];
    for (int i = 0; i < 12; i++) /* transposed, as LAPACK saw it */
        for (int j = 0; j < 12; j++) {
            int k = 12 * i + j;
            a[12 * j + i] = (m2[k] * x + m1[k]) * x + m0[k];
        }
    lu12(a, ipiv, 0.0);
    double small = INFINITY, big = 0.0;
    for (int i = 0; i < 12; i++) small = fmin(small, fabs(a[13 * i])), big = fmax(big, fabs(a[13 * i]));
    return !(small > SINGULAR * big);
}

/* The null vector of lead mu^2 + middle mu + tail (12x12 row-major) at a root mu: two steps of
   inverse iteration, scaled so that its largest entry is positive (the eigenvector the companion
   matrix's eigenproblem would give, without computing the 24 of them). */
/* A root whose matrix has two LU pivots below MULTIPLE times the largest: a null space of two
   dimensions (solutions sharing the eliminated joint's angle, which the NumPy path's careful
   pass reads: _general_6r_elimination._multiple_roots). Exact multiple roots (round joint
   angles) give 1e-15; the near-double roots of random poses 1e-11 or more (PiPER), which the
   fallbacks and the nudged poses resolve with the NumPy path's branches. */
#define MULTIPLE 1e-12
static int null_vector(const double *lead, const double *middle, const double *tail, double mu,
                       double *v)
{
    double a[144], scale = 0.0;
    for (int k = 0; k < 144; k++) {
        a[k] = (lead[k] * mu + middle[k]) * mu + tail[k];
        double size = fabs(a[k]);
        if (size > scale) scale = size; /* fmax, but inline (a NaN entry is skipped as by fmax) */
    }
    int piv[12];
    lu12(a, piv, 1e-300 + scale * 1e-18);
    double largest = 0.0;
    int small = 0;
    for (int i = 0; i < 12; i++) largest = fmax(largest, fabs(a[13 * i]));
    for (int i = 0; i < 12; i++) small += !(fabs(a[13 * i]) > MULTIPLE * largest);
    for (int i = 0; i < 12; i++) v[i] = 1.0 + 0.1 * i; /* a generic start */
    for (int step = 0; step < 2; step++) {
        for (int c = 0; c < 12; c++) { /* P b */
            double t = v[piv[c]];
            v[piv[c]] = v[c], v[c] = t;
        }
        for (int c = 0; c < 12; c++) /* L y = P b */
            for (int r = c + 1; r < 12; r++) v[r] -= a[12 * r + c] * v[c];
        for (int c = 11; c >= 0; c--) { /* U x = y */
            double t = v[c];
            for (int k = c + 1; k < 12; k++) t -= a[12 * c + k] * v[k];
            v[c] = t / a[13 * c];
        }
        double big = 0.0;
        for (int i = 0; i < 12; i++)
            if (fabs(v[i]) > fabs(big)) big = v[i];
        for (int i = 0; i < 12; i++) v[i] = big != 0.0 && isfinite(big) ? v[i] / big : 0.0;
    }
    return small >= 2;
}

/* The eigenvalues (wr + i wi) of the n x n column-major a (overwritten): dgeev's own steps
   without eigenvectors, called one by one (dgebal, dgehd2, dlahqr: the same numbers, without
   the workspace queries and ilaenv look-ups that dgeev and dhseqr make on every call), or
   dgeev itself where it would scale a or dlahqr fails. 0, or LAPACK's info. */
#define SAFE_NORM 1e130 /* well inside dgeev's [smlnum, bignum] = [6.7e-139, 1.5e138] */
static int eigenvalues(double *a, int n, double *wr, double *wi, double *work, int lwork)
{
    double copy[24 * 24], size = 0.0;
    int info = 0, ilo, ihi, one = 1, no_vectors = 0;
    for (int k = 0; k < n * n; k++) {
        double x = fabs(a[k]);
        if (!(x <= size)) size = x; /* NaN taken, as dlange does */
    }
    if (!(size > 1.0 / SAFE_NORM && size < SAFE_NORM)) { /* dgeev would scale (or a is 0) */
        char no = 'N';
        double vl[1];
        dgeev_(&no, &no, &n, a, &n, wr, wi, vl, &one, vl, &one, work, &lwork, &info);
        return info;
    }
    memcpy(copy, a, (size_t)(n * n) * sizeof(double));
    char both = 'B';
    dgebal_(&both, &n, a, &n, &ilo, &ihi, work, &info);
    if (info == 0) dgehd2_(&n, &ilo, &ihi, a, &n, work + n, work + 2 * n, &info);
    if (info != 0) return info;
    for (int i = 0; i < n; i++) /* dhseqr: the eigenvalues dgebal isolated */
        if (i < ilo - 1 || i >= ihi) wr[i] = a[i + n * i], wi[i] = 0.0;
    if (ilo == ihi) {
        wr[ilo - 1] = a[(ilo - 1) * (n + 1)], wi[ilo - 1] = 0.0;
        return 0;
    }
    dlahqr_(&no_vectors, &no_vectors, &n, &ilo, &ihi, a, &n, wr, wi, &ilo, &ihi, work, &one, &info);
    if (info > 0) { /* dhseqr would go on with dlaqr0: dgeev answers */
        char no = 'N';
        double vl[1];
        memcpy(a, copy, (size_t)(n * n) * sizeof(double));
        dgeev_(&no, &no, &n, a, &n, wr, wi, vl, &one, vl, &one, work, &lwork, &info);
    }
    return info;
}

/* Householder QR of the 14x8 column-major a (overwritten): q the full 14x14 orthogonal factor
   (column-major), r the 8x8 triangle (row-major, upper). 1, or 0 (q, r anything) when a diagonal
   of r is below QR_RANK times the largest (near rank-deficient: the caller takes the SVD). */
#define QR_RANK 1e-10
static int qr14x8(double *a, double *q, double *r)
{
    double v[8][14], beta[8], big = 0.0, least = INFINITY;
    for (int j = 0; j < 8; j++) {
        double norm = 0.0;
        for (int i = j; i < 14; i++) norm += a[i + 14 * j] * a[i + 14 * j];
        norm = sqrt(norm);
        double alpha = a[j + 14 * j] > 0.0 ? -norm : norm, vv = 0.0;
        for (int i = 0; i < 14; i++) {
            v[j][i] = i < j ? 0.0 : (i == j ? a[j + 14 * j] - alpha : a[i + 14 * j]);
            vv += v[j][i] * v[j][i];
        }
        beta[j] = vv > 0.0 ? 2.0 / vv : 0.0;
        for (int k = j; k < 8; k++) { /* H_j on the columns left */
            double t = 0.0;
            for (int i = j; i < 14; i++) t += v[j][i] * a[i + 14 * k];
            t *= beta[j];
            for (int i = j; i < 14; i++) a[i + 14 * k] -= t * v[j][i];
        }
        big = fmax(big, fabs(a[j + 14 * j]));
        least = fmin(least, fabs(a[j + 14 * j]));
    }
    if (!(least > QR_RANK * big)) return 0;
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 8; j++) r[8 * i + j] = j < i ? 0.0 : a[i + 14 * j];
    for (int k = 0; k < 196; k++) q[k] = k % 15 == 0 ? 1.0 : 0.0; /* the identity */
    for (int j = 7; j >= 0; j--) /* q = H_0 ... H_7 I */
        for (int k = 0; k < 14; k++) {
            double t = 0.0;
            for (int i = j; i < 14; i++) t += v[j][i] * q[i + 14 * k];
            t *= beta[j];
            for (int i = j; i < 14; i++) q[i + 14 * k] -= t * v[j][i];
        }
    return 1;
}

/* The first pass of one pose T, its candidates polished onto target (T itself, or the pose a
   nudged T was taken near): 0, or -1 when the NumPy path must answer. */
static int one_pose(const double *arm, const double *T, const double *target, double *out,
                    double *roots)
{
    int a = (int)arm[ARM_START], reverse = arm[ARM_REVERSE] != 0.0;
    const double *Cf = arm + ARM_C, *Ci = arm + ARM_CINV, *P = arm + ARM_P, *F = arm + ARM_F;
    const double *fit = arm + ARM_FIT9, *tau = arm + ARM_TAU;
    double K[16], tmp[16], G[16], Ginv[16];
    const double *C[6], *Cinv[6];
    mul4(arm + ARM_F0INV, T, tmp);
    mul4(tmp, arm + ARM_F6INV, K);
    if (reverse) memcpy(G, K, sizeof G), rigid_inverse(K, Ginv);
    else rigid_inverse(K, G), memcpy(Ginv, K, sizeof Ginv);
    for (int k = 0; k < 5; k++) C[k] = Cf + 16 * k, Cinv[k] = Ci + 16 * k;
    C[5] = G, Cinv[5] = Ginv;
    int i3 = (a + 3) % 6, i4 = (a + 4) % 6, i5 = (a + 5) % 6;
    /* Right side at the 9 grid points, fitted on {1, s, c}^2: Q (14x9). */
    double values[9][14], Q[14][9];
    double head[3][16]; /* C_i5^-1 Rz(-u_i5) C_i4^-1 at the 3 grid angles of u_i5 */
    for (int j = 0; j < 3; j++) {
        mul_rz(Cinv[i5], -GRID[j], tmp);
        mul4(tmp, Cinv[i4], head[j]);
    }
    for (int g = 0; g < 9; g++) { /* u_i4 = GRID[g / 3] (slow), u_i5 = GRID[g % 3] */
        double x[16], y[16];
        mul_rz(head[g % 3], -GRID[g / 3], x);
        mul4(x, Cinv[i3], y);
        equations(y, values[g]);
    }
    for (int k = 0; k < 14; k++)
        for (int i = 0; i < 9; i++) {
            double s = 0.0;
            for (int j = 0; j < 9; j++) s += fit[9 * i + j] * values[j][k];
            Q[k][i] = s;
        }
    /* Q[:, 1:] (column-major 14x8): its Householder QR (U the full Q, its last 6 columns the
       left null space), or where R is near-singular its SVD (LAPACK dgesvd). */
    double A[14 * 8], U[14 * 14], sv[8], Vt[8 * 8], work[1024];
    int m14 = 14, n8 = 8, lwork = 1024, info;
    for (int j = 0; j < 8; j++)
        for (int i = 0; i < 14; i++) A[i + 14 * j] = Q[i][j + 1];
    double R[8 * 8];
    int by_qr = qr14x8(A, U, R);
    if (!by_qr) {
        for (int j = 0; j < 8; j++)
            for (int i = 0; i < 14; i++) A[i + 14 * j] = Q[i][j + 1];
        char all = 'A';
        dgesvd_(&all, &all, &m14, &n8, A, &m14, sv, U, &m14, Vt, &n8, work, &lwork, &info);
        if (info != 0) return -1;
    }
    /* M_k (12x12 row-major): [S 0; 0 S] shifted, S = null P_k. */
    double M[3][144];
    memset(M, 0, sizeof M);
    for (int k = 0; k < 3; k++)
        for (int r = 0; r < 6; r++)
            for (int c = 0; c < 9; c++) {
                double s = 0.0;
                for (int i = 0; i < 14; i++) {
                    double p = P[(k * 14 + i) * 9 + c];
                    if (k != 1 && (c == 0 || c == 2 || c == 6 || c == 8)) p -= Q[i][0];
                    s += U[i + 14 * (8 + r)] * p;
                }
                M[k][12 * r + c] = s;
                M[k][12 * (6 + r) + 3 + c] = s;
            }
    /* A singular pencil (M(x) singular at every x: some solutions of the pose form curves, as
       where a 55 deg wrist makes axes 4 and 6 parallel) has eigenvalues that depend on the
       LAPACK build: the NumPy path answers that pose (its nudged poses). */
    if (singular_pencil(M[0], M[1], M[2])) return -1;
    /* Companion matrix on the better conditioned leading matrix. */
    int flip = hadamard_ratio(M[0]) > hadamard_ratio(M[2]);
    const double *lead = flip ? M[0] : M[2], *tail = flip ? M[2] : M[0];
    double L[144], rhs[12 * 24], comp[24 * 24];
    int n12 = 12, n24 = 24, ipiv[12];
    for (int i = 0; i < 12; i++)
        for (int j = 0; j < 12; j++) {
            L[i + 12 * j] = lead[12 * i + j];
            rhs[i + 12 * j] = tail[12 * i + j];
            rhs[i + 12 * (12 + j)] = M[1][12 * i + j];
        }
    dgesv_(&n12, &n24, L, &n12, ipiv, rhs, &n12, &info);
    if (info != 0) return -1;
    memset(comp, 0, sizeof comp);
    for (int i = 0; i < 12; i++) comp[i + 24 * (12 + i)] = 1.0;
    for (int i = 0; i < 12; i++)
        for (int j = 0; j < 24; j++) {
            double v = -rhs[i + 12 * j];
            if (!isfinite(v)) return -1;
            comp[12 + i + 24 * j] = v;
        }
    /* The 8 spurious eigenvalues (x = +-i) deflated: the eigenvalues of Q2^T A Q2 (m x m). */
    int m = (int)arm[ARM_DEFLATED];
    double *eig = comp, B[24 * 24];
    if (m < 24) {
        const double *Q2 = arm + ARM_BASES + (flip ? 576 : 0);
        double AQ[24][24];
        for (int i = 0; i < 12; i++) /* A's top rows are [0 I] */
            for (int j = 0; j < m; j++) AQ[i][j] = Q2[24 * (12 + i) + j];
        /* The products row by row (each entry's sum in the same order, the j loops vectorised). */
        for (int i = 12; i < 24; i++) {
            for (int j = 0; j < m; j++) AQ[i][j] = 0.0;
            for (int l = 0; l < 24; l++) {
                double c = comp[i + 24 * l];
                for (int j = 0; j < m; j++) AQ[i][j] += c * Q2[24 * l + j];
            }
        }
        for (int r = 0; r < m; r++) {
            double t[24] = {0.0};
            for (int i = 0; i < 24; i++) {
                double q = Q2[24 * i + r];
                for (int j = 0; j < m; j++) t[j] += q * AQ[i][j];
            }
            for (int j = 0; j < m; j++) B[r + m * j] = t[j];
        }
        eig = B;
    }
    double wr[24], wi[24];
    if (eigenvalues(eig, m, wr, wi, work, lwork) != 0) return -1;
    /* The least squares of the right side's monomials: pinv of Q[:, 1:] (8x14), R^-1 Q1^T from
       its QR, else from its SVD (singular values below 1e-12 of the largest dropped). */
    double pinv[8][14], inv[8];
    if (by_qr) {
        for (int k = 0; k < 14; k++)
            for (int i = 7; i >= 0; i--) { /* R x = (row k of Q1)^T */
                double t = U[k + 14 * i];
                for (int j = i + 1; j < 8; j++) t -= R[8 * i + j] * pinv[j][k];
                pinv[i][k] = t / R[9 * i];
            }
    } else {
        for (int r = 0; r < 8; r++)
            inv[r] = sv[r] > sv[0] * 1e-12 ? 1.0 / (sv[r] > 0 ? sv[r] : 1.0) : 0.0;
        for (int i = 0; i < 8; i++)
            for (int k = 0; k < 14; k++) {
                double s = 0.0;
                for (int r = 0; r < 8; r++) s += Vt[r + 8 * i] * inv[r] * U[k + 14 * r];
                pinv[i][k] = s;
            }
    }
    /* Each (near-)real root: the joints, polished. */
    double rows[24 * 6];
    int kept = 0, count = 0, multiple = 0;
    for (int e = 0; e < m; e++) {
        double im = fabs(wi[e]) / (1.0 + hypot(wr[e], wi[e]));
        if (!(im <= IMAG_TOL)) continue;
        double v[12];
        multiple |= null_vector(lead, M[1], tail, wr[e], v);
        double theta = tau[0] + 2.0 * (flip ? atan2(1.0, wr[e]) : atan2(wr[e], 1.0));
        double phi = tau[1] + 2.0 * ratio_angle(v, 1), psi = tau[2] + 2.0 * ratio_angle(v, 0);
        /* The right side's joints from the monomials (least squares on Q), u_a+3 from the loop. */
        double Lt[16], x[16], f[14], mono[8], u[6];
        double ct = cos(theta), st = sin(theta);
        for (int k = 0; k < 4; k++) {
            x[k] = ct * C[a][k] - st * C[a][4 + k];
            x[4 + k] = st * C[a][k] + ct * C[a][4 + k];
            x[8 + k] = C[a][8 + k];
            x[12 + k] = C[a][12 + k];
        }
        mul_rz(x, phi, tmp);
        mul4(tmp, C[a + 1], x);
        mul_rz(x, psi, tmp);
        mul4(tmp, C[a + 2], Lt);
        equations(Lt, f);
        for (int i = 0; i < 14; i++) f[i] -= Q[i][0];
        for (int i = 0; i < 8; i++) {
            double s = 0.0;
            for (int k = 0; k < 14; k++) s += pinv[i][k] * f[k];
            mono[i] = s;
        }
        u[a] = theta, u[(a + 1) % 6] = phi, u[(a + 2) % 6] = psi;
        u[i5] = atan2(mono[0], mono[1]);
        u[i4] = atan2(mono[2], mono[5]);
        double R[16];
        mul_rz(C[i3], u[i4], tmp);
        mul4(tmp, C[i4], x);
        mul_rz(x, u[i5], tmp);
        mul4(tmp, C[i5], R);
        double Z[9]; /* (R L)^T, rotation parts */
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                Z[3 * j + i] = R[4 * i] * Lt[j] + R[4 * i + 1] * Lt[4 + j] + R[4 * i + 2] * Lt[8 + j];
        u[i3] = atan2(Z[3] - Z[1], Z[0] + Z[4]);
        double q[6];
        int finite = 1;
        for (int k = 0; k < 6; k++) {
            q[reverse ? 5 - k : k] = reverse ? -u[k] : u[k];
            if (!isfinite(u[k])) finite = 0;
        }
        if (!finite) continue;
        if (im <= ROOT_TOL) count++;
        if (polish(F, q, target) <= KEEP_TOL) memcpy(rows + 6 * kept++, q, sizeof q);
    }
    *roots = (double)count;
    distinct(rows, kept, out);
    if (multiple) { /* unclean at a multiple root: -2 (the NumPy path's careful pass answers) */
        int found = 0;
        while (found < BRANCHES && !isnan(out[6 * found])) found++;
        if (found < count || found % 2 == 1) *roots = -2.0;
    }
    return 0;
}

/* A C-contiguous float64 buffer of n values, or 0 with a TypeError. */
static int doubles(PyObject *obj, Py_buffer *view, Py_ssize_t n, int writable, const char *what)
{
    if (PyObject_GetBuffer(obj, view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0)) != 0)
        return 0;
    if (view->itemsize != sizeof(double) || view->format == NULL || strcmp(view->format, "d") != 0 ||
        view->len != n * (Py_ssize_t)sizeof(double)) {
        PyBuffer_Release(view);
        PyErr_Format(PyExc_TypeError, "%s must be %zd contiguous float64 values", what, n);
        return 0;
    }
    return 1;
}

static PyObject *first_pass(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs != 4 && nargs != 5) {
        PyErr_SetString(PyExc_TypeError, "first_pass(arm, T, out, roots[, targets])");
        return NULL;
    }
    Py_buffer arm, T, out, roots, targets;
    if (!doubles(args[0], &arm, ARM_SIZE, 0, "arm")) return NULL;
    Py_ssize_t n = PyObject_Length(args[3]);
    if (n < 0) {
        PyBuffer_Release(&arm);
        return NULL;
    }
    if (!doubles(args[1], &T, 16 * n, 0, "T (N, 4, 4)")) {
        PyBuffer_Release(&arm);
        return NULL;
    }
    if (!doubles(args[2], &out, BRANCHES * 6 * n, 1, "out (N, 16, 6)")) {
        PyBuffer_Release(&arm), PyBuffer_Release(&T);
        return NULL;
    }
    if (!doubles(args[3], &roots, n, 1, "roots (N,)")) {
        PyBuffer_Release(&arm), PyBuffer_Release(&T), PyBuffer_Release(&out);
        return NULL;
    }
    if (nargs == 5 && !doubles(args[4], &targets, 16 * n, 0, "targets (N, 4, 4)")) {
        PyBuffer_Release(&arm), PyBuffer_Release(&T), PyBuffer_Release(&out);
        PyBuffer_Release(&roots);
        return NULL;
    }
    const double *a = arm.buf, *t = T.buf, *g = nargs == 5 ? targets.buf : T.buf;
    double *o = out.buf, *r = roots.buf;
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t k = 0; k < n; k++)
        if (one_pose(a, t + 16 * k, g + 16 * k, o + BRANCHES * 6 * k, r + k) != 0) r[k] = -1.0;
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&arm), PyBuffer_Release(&T), PyBuffer_Release(&out), PyBuffer_Release(&roots);
    if (nargs == 5) PyBuffer_Release(&targets);
    Py_RETURN_NONE;
}

/* solve_one(arm, position, rotation, signs, out): the first pass of one world pose (position
   (3,) [m], rotation (3, 3), contiguous float64), its branches times the joints' signs (6,)
   into out (16, 6) when the pass answers it cleanly (as many distinct branches as real roots,
   an even number): returns 1; else 0 (the caller takes the whole path), out anything. */
static PyObject *solve_one(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError, "solve_one(arm, position, rotation, signs, out)");
        return NULL;
    }
    Py_buffer v[5];
    static const Py_ssize_t sizes[5] = {ARM_SIZE, 3, 9, 6, BRANCHES * 6};
    static const char *const names[5] = {"arm", "position", "rotation", "signs", "out"};
    int got = 0;
    for (; got < 5; got++)
        if (!doubles(args[got], &v[got], sizes[got], got == 4, names[got])) break;
    if (got < 5) {
        for (int k = 0; k < got; k++) PyBuffer_Release(&v[k]);
        PyErr_Clear(); /* not the arrays this short way takes: the caller's whole path */
        Py_RETURN_FALSE;
    }
    const double *p = v[1].buf, *r = v[2].buf, *signs = v[3].buf;
    double *out = v[4].buf, T[16] = {0.0}, roots = 0.0;
    int finite = 1;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) T[4 * i + j] = r[3 * i + j];
        T[4 * i + 3] = p[i];
    }
    T[15] = 1.0;
    for (int k = 0; k < 16; k++) finite &= isfinite(T[k]) != 0;
    int clean = 0;
    if (finite && one_pose(v[0].buf, T, T, out, &roots) == 0) {
        int found = 0;
        while (found < BRANCHES && !isnan(out[6 * found])) found++;
        clean = roots >= 0.0 && found >= roots && found % 2 == 0;
        for (int k = 0; k < 6 * found; k++) out[k] *= signs[k % 6];
    }
    for (int k = 0; k < 5; k++) PyBuffer_Release(&v[k]);
    return PyBool_FromLong(clean);
}

/* verify(check, q, seeds, positions, rotations, info): the 16 branches of each of N targets
   moved into the limits (in place) and measured, as the 6R twins' verify does for 8
   (check_branches_n in _six_r_twin.h: the limit rule, a plain DH product of the table as the
   judge): check the block of kin.ik.analytic.six_r.six_r_twin.check_params (CHECK_LAYOUT), q
   (N, 16, 6) [rad] (NaN rows: no branch), seeds (N, 6) [rad], positions (N, 3) [m], rotations
   (N, 3, 3), info (N, 16, 4) per branch: status (0 no branch, 1 valid, 2 outside the limits,
   3 off target), position error [m], rotation error [rad], distance to the seed [rad]. */
static PyObject *verify(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 6) {
        PyErr_SetString(PyExc_TypeError, "verify(check, q, seeds, positions, rotations, info)");
        return NULL;
    }
    Py_ssize_t n = PyObject_Length(args[3]);
    if (n < 0) return NULL;
    Py_buffer v[6];
    const Py_ssize_t sizes[6] = {CHECK_COUNT, BRANCHES * 6 * n, 6 * n, 3 * n, 9 * n, BRANCHES * 4 * n};
    static const char *const names[6] = {"check", "q (N, 16, 6)", "seeds (N, 6)", "positions (N, 3)",
                                         "rotations (N, 3, 3)", "info (N, 16, 4)"};
    int got = 0;
    for (; got < 6; got++)
        if (!doubles(args[got], &v[got], sizes[got], got == 1 || got == 5, names[got])) break;
    if (got < 6) {
        for (int k = 0; k < got; k++) PyBuffer_Release(&v[k]);
        return NULL;
    }
    const Check *C = v[0].buf;
    double(*q)[BRANCHES][JOINTS] = v[1].buf, (*info)[BRANCHES][4] = v[5].buf;
    const double *seeds = v[2].buf, *p = v[3].buf, *r = v[4].buf;
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t k = 0; k < n; k++)
        check_branches_n(C, p + 3 * k, r + 9 * k, seeds + 6 * k, BRANCHES, q[k], info[k]);
    Py_END_ALLOW_THREADS
    for (int k = 0; k < 6; k++) PyBuffer_Release(&v[k]);
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    {"first_pass", (PyCFunction)(void (*)(void))first_pass, METH_FASTCALL,
     "first_pass(arm, T, out, roots[, targets]): the general 6R closed form's first pass of N "
     "poses (polished onto targets when given)."},
    {"solve_one", (PyCFunction)(void (*)(void))solve_one, METH_FASTCALL,
     "solve_one(arm, position, rotation, signs, out): one pose's clean first pass, or False."},
    {"verify", (PyCFunction)(void (*)(void))verify, METH_FASTCALL,
     "verify(check, q, seeds, positions, rotations, info): N targets' 16 branches moved into the "
     "limits and measured (see kin/_native/ik/analytic/six_r/_general6r.c)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_general6r", NULL, -1, methods};

/* A LAPACK routine's pointer from SciPy's cython_lapack capsules, or NULL with an ImportError. */
static void *lapack(PyObject *capi, const char *name)
{
    PyObject *capsule = PyDict_GetItemString(capi, name);
    if (capsule == NULL) {
        PyErr_Format(PyExc_ImportError, "scipy.linalg.cython_lapack has no %s", name);
        return NULL;
    }
    return PyCapsule_GetPointer(capsule, PyCapsule_GetName(capsule));
}

PyMODINIT_FUNC PyInit__general6r(void)
{
    PyObject *lapack_module = PyImport_ImportModule("scipy.linalg.cython_lapack");
    if (lapack_module == NULL) return NULL;
    PyObject *capi = PyObject_GetAttrString(lapack_module, "__pyx_capi__");
    Py_DECREF(lapack_module);
    if (capi == NULL) return NULL;
    dgeev_ = (dgeev_t *)lapack(capi, "dgeev");
    dgesvd_ = (dgesvd_t *)lapack(capi, "dgesvd");
    dgesv_ = (dgesv_t *)lapack(capi, "dgesv");
    dgebal_ = (dgebal_t *)lapack(capi, "dgebal");
    dgehd2_ = (dgehd2_t *)lapack(capi, "dgehd2");
    dlahqr_ = (dlahqr_t *)lapack(capi, "dlahqr");
    Py_DECREF(capi);
    if (!dgeev_ || !dgesvd_ || !dgesv_ || !dgebal_ || !dgehd2_ || !dlahqr_) return NULL;
    PyObject *m = PyModule_Create(&module);
    if (m == NULL) return NULL;
    if (add_layout(m, "CHECK_LAYOUT", CHECK_FIELDS, sizeof CHECK_FIELDS / sizeof CHECK_FIELDS[0]) < 0 ||
        PyModule_AddIntConstant(m, "CHECK_COUNT", CHECK_COUNT) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}

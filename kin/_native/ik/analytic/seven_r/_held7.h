/*
 * The branches of a 7R arm at values of a held joint, from an idealised arm's closed form: the
 * compiled twin of kin/ik/analytic/seven_r/general_7r.py's General7RIK._held. Included by
 * _closed7.c, which defines
 *   static int branches_folds(const Params *P, const double *T, double value, double (*sol)[7],
 *                             double *fold);
 * the idealised form's branches at one free-joint value of the prepared target T, and the least
 * fold_distance (kin/ik/analytic/seven_r/subproblems.py) of the equations it solved.
 *
 * Each branch of the idealised arm (its twists and small lengths snapped, its tool within
 * micrometres of the true one) at a held value starts Newton steps on the TRUE chain (the Seed
 * block's DH product, chain_step in _twin.h) over the six other joints, the held one fixed:
 * the steps of kin/ik/analytic/six_r/_general_6r_chain.polish (J^T (J J^T + 1e-14 I)^-1 e,
 * here J^-1 e where J is regular, each joint's step clipped to 0.5 rad; at most 8 steps; a row
 * stops on target to 1e-12 or off it by 1 or more), the error vector in the world frame (the
 * Python form's in the frame after the held joint: the same steps up to rounding). A row kept has its largest error at most
 * keep_tol; its six polished joints wrapped into [-pi, pi). A value whose least fold distance is
 * below fold_margin (the true arm may have a pair of branches more or fewer there) gets no rows:
 * its count is -1, for the caller's 6R elimination. Angles [rad], lengths [m].
 *
 * held_rows(params, ideal_block, chain_block, target, values, free, keep_tol, fold_margin, out,
 *           counts)
 *   params:      bytes of the idealised form's Params without limits (joints in [-pi, pi]);
 *   ideal_block: bytes of its Seed block (the frames its target is prepared in);
 *   chain_block: bytes of a Seed block of the true table (twin_support.chain_block);
 *   target:      a full pose (target_values in _twin.h);
 *   values:      float64[G], the held joint's values [rad];
 *   free:        the held joint (0-based);
 *   keep_tol:    the largest error of a kept row [m], [rad];
 *   fold_margin: the least fold distance of a value answered here;
 *   out:         float64[G * 8, 7], receives the kept rows in order (value by value);
 *   counts:      float64[G], receives each value's count of rows (-1: left to the caller).
 *   Returns how many rows it wrote; -1 when the target is not a finite pose.
 */
#ifndef KIN_IK_ANALYTIC_SEVEN_R_HELD7_H
#define KIN_IK_ANALYTIC_SEVEN_R_HELD7_H

#define HELD_STEPS 8      /* _general_6r_chain.NEWTON_STEPS */
#define HELD_TOL 1e-12    /* _general_6r_chain.NEWTON_TOL [m], [rad] */
#define HELD_CLIP 0.5     /* the largest step of a joint [rad] */
#define HELD_DAMPING 1e-14 /* _general_6r_chain._DAMPING */

/* The tool pose (3x4) of the chain at q, and the axis and a point on it (world) of each joint
   from `first` on; start: the pose (3x4) before row `first` (the base, or the held first joint's
   frame: the same at every step). */
static void held_frames(const Seed *S, const double *start, int first, const double *q, double *T,
                        double (*axis)[3], double (*origin)[3])
{
    double a[12], b[12];
    const double *previous = start;
    const int modified = S->modified[0] != 0.0;
    for (int j = first; j < 7; j++) {
        double *next = j % 2 ? b : a;
        chain_step(modified, S->a[j], S->cos_alpha[j], S->sin_alpha[j], S->d[j], q[j] + S->theta[j],
                   previous, next);
        const double *at = modified ? next : previous; /* the frame whose z is the joint's axis */
        for (int i = 0; i < 3; i++) axis[j][i] = at[4 * i + 2], origin[j][i] = at[4 * i + 3];
        previous = next;
    }
    chain_compose(previous, S->tool, T);
}

/* The error vector (position, small-angle rotation) of pose T to p, r and its size: the largest
   entry, or infinity when the rotation is more than 90 deg off (_general_6r_chain._errors). */
static double held_error(const double *T, const double *p, const double *r, double *e)
{
    double E[9]; /* r T_R^T */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            E[3 * i + j] = r[3 * i] * T[4 * j] + r[3 * i + 1] * T[4 * j + 1] + r[3 * i + 2] * T[4 * j + 2];
    for (int i = 0; i < 3; i++) e[i] = p[i] - T[4 * i + 3];
    e[3] = 0.5 * (E[7] - E[5]);
    e[4] = 0.5 * (E[2] - E[6]);
    e[5] = 0.5 * (E[3] - E[1]);
    double size = 0.0;
    for (int i = 0; i < 6; i++) size = fabs(e[i]) > size ? fabs(e[i]) : size;
    if (isnan(size)) return size;
    return E[0] + E[4] + E[8] > 1.0 ? size : INFINITY;
}

/* x = A^-1 b for a 6x6 A (row-major, overwritten) by Gaussian elimination with partial
   pivoting, b overwritten by x; 0 when a pivot is 0 (singular). */
static int held_solve6(double *A, double *b)
{
    for (int c = 0; c < 6; c++) {
        int pivot = c;
        double best = fabs(A[6 * c + c]);
        for (int i = c + 1; i < 6; i++)
            if (fabs(A[6 * i + c]) > best) best = fabs(A[6 * i + c]), pivot = i;
        if (!(best > 0.0)) return 0;
        if (pivot != c) {
            for (int j = c; j < 6; j++) {
                double t = A[6 * c + j];
                A[6 * c + j] = A[6 * pivot + j], A[6 * pivot + j] = t;
            }
            double t = b[c];
            b[c] = b[pivot], b[pivot] = t;
        }
        double inverse = 1.0 / A[6 * c + c];
        A[6 * c + c] = inverse;
        for (int i = c + 1; i < 6; i++) {
            double f = A[6 * i + c] * inverse;
            for (int j = c + 1; j < 6; j++) A[6 * i + j] -= f * A[6 * c + j];
            b[i] -= f * b[c];
        }
    }
    for (int i = 5; i >= 0; i--) {
        double sum = b[i];
        for (int j = i + 1; j < 6; j++) sum -= A[6 * i + j] * b[j];
        b[i] = sum * A[6 * i + i];
    }
    return 1;
}

/* Newton steps of q (7) on the chain towards p, r, joint `free` held; the last error size. Each
   step solves J s = e (6x6, partial pivoting): the minimum-norm step of the Python form, which
   damps J J^T by 1e-14, where J is regular; else that damped step. */
static double held_polish(const Seed *S, double *q, int free, const double *p, const double *r)
{
    double size = INFINITY, held[12];
    const double *start = S->base;
    int first = 0;
    if (free == 0) { /* the held first joint's frame, once */
        chain_step(S->modified[0] != 0.0, S->a[0], S->cos_alpha[0], S->sin_alpha[0], S->d[0],
                   q[0] + S->theta[0], S->base, held);
        start = held;
        first = 1;
    }
    for (int step = 0; step <= HELD_STEPS; step++) {
        double T[12], axis[7][3], origin[7][3], e[6], J[6][6], A[36], s[6];
        held_frames(S, start, first, q, T, axis, origin);
        size = held_error(T, p, r, e);
        if (step == HELD_STEPS || !(size > HELD_TOL && size < 1.0)) break;
        int moving[6];
        for (int j = 0, c = 0; j < 7; j++) {
            if (j == free) continue;
            moving[c] = j;
            const double *z = axis[j];
            double v[3] = {T[3] - origin[j][0], T[7] - origin[j][1], T[11] - origin[j][2]};
            J[0][c] = z[1] * v[2] - z[2] * v[1];
            J[1][c] = z[2] * v[0] - z[0] * v[2];
            J[2][c] = z[0] * v[1] - z[1] * v[0];
            J[3][c] = z[0], J[4][c] = z[1], J[5][c] = z[2];
            c++;
        }
        memcpy(A, J, sizeof A);
        memcpy(s, e, sizeof s);
        if (!held_solve6(A, s)) { /* J singular: J^T (J J^T + 1e-14 I)^-1 e */
            for (int i = 0; i < 6; i++)
                for (int k = 0; k < 6; k++) {
                    double sum = i == k ? HELD_DAMPING : 0.0;
                    for (int c = 0; c < 6; c++) sum += J[i][c] * J[k][c];
                    A[6 * i + k] = sum;
                }
            if (!held_solve6(A, e)) return INFINITY;
            for (int c = 0; c < 6; c++) {
                s[c] = 0.0;
                for (int i = 0; i < 6; i++) s[c] += J[i][c] * e[i];
            }
        }
        for (int c = 0; c < 6; c++) {
            double delta = s[c] < -HELD_CLIP ? -HELD_CLIP : s[c] > HELD_CLIP ? HELD_CLIP : s[c];
            q[moving[c]] += delta;
        }
    }
    return size;
}

/* np.remainder(x + pi, 2 pi) - pi. */
static inline double held_wrap(double x)
{
    double m = fmod(x + M_PI, TWO_PI);
    if (m < 0.0) m += TWO_PI;
    return m - M_PI;
}

static PyObject *held_rows(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 10) {
        PyErr_SetString(PyExc_TypeError, "held_rows(params, ideal_block, chain_block, target, "
                                         "values, free, keep_tol, fold_margin, out, counts)");
        return NULL;
    }
    Params P;
    Seed I, S;
    if (!PyBytes_Check(args[0]) || PyBytes_GET_SIZE(args[0]) != sizeof P ||
        !PyBytes_Check(args[1]) || PyBytes_GET_SIZE(args[1]) != sizeof I ||
        !PyBytes_Check(args[2]) || PyBytes_GET_SIZE(args[2]) != sizeof S) {
        PyErr_SetString(PyExc_ValueError, "params, ideal_block, chain_block: bytes of the blocks");
        return NULL;
    }
    memcpy(&P, PyBytes_AS_STRING(args[0]), sizeof P);
    memcpy(&I, PyBytes_AS_STRING(args[1]), sizeof I);
    memcpy(&S, PyBytes_AS_STRING(args[2]), sizeof S);
    long free = PyLong_AsLong(args[5]);
    double keep = PyFloat_AsDouble(args[6]), margin = PyFloat_AsDouble(args[7]);
    if (PyErr_Occurred()) return NULL;
    if (free < 0 || free > 6) {
        PyErr_SetString(PyExc_ValueError, "free: a joint index 0-6");
        return NULL;
    }
    double p[3], r[9];
    if (target_values(args[3], p, r) != 0 || !all_finite(p, 3) || !all_finite(r, 9)) {
        PyErr_Clear();
        return PyLong_FromLong(-1);
    }
    Py_buffer values, out, counts;
    if (!get_doubles(args[4], &values, 0, "values")) return NULL;
    if (!get_doubles(args[8], &out, 1, "out")) {
        PyBuffer_Release(&values);
        return NULL;
    }
    if (!get_doubles(args[9], &counts, 1, "counts")) {
        PyBuffer_Release(&values);
        PyBuffer_Release(&out);
        return NULL;
    }
    Py_ssize_t g = values.len / (Py_ssize_t)sizeof(double), n = 0;
    if (out.len < g * 8 * 7 * (Py_ssize_t)sizeof(double) || counts.len < values.len) {
        PyBuffer_Release(&values);
        PyBuffer_Release(&out);
        PyBuffer_Release(&counts);
        PyErr_SetString(PyExc_ValueError, "out: float64[G * 8, 7]; counts: float64[G]");
        return NULL;
    }
    double T[12], (*rows)[7] = out.buf, *count = counts.buf;
    const double *grid = values.buf;
    prepare_seeded(&I, 0, p, r, T);
    for (Py_ssize_t k = 0; k < g; k++) {
        double sol[8][7], fold = INFINITY;
        int found = branches_folds(&P, T, grid[k], sol, &fold);
        Py_ssize_t before = n;
        count[k] = -1.0;
        if (fold < margin) continue;
        for (int b = 0; b < found; b++) {
            if (!all_finite(sol[b], 7)) continue;
            sol[b][free] = grid[k];
            if (!(held_polish(&S, sol[b], (int)free, p, r) <= keep)) continue;
            for (int j = 0; j < 7; j++) rows[n][j] = j == free ? grid[k] : held_wrap(sol[b][j]);
            n++;
        }
        count[k] = (double)(n - before);
    }
    PyBuffer_Release(&values);
    PyBuffer_Release(&out);
    PyBuffer_Release(&counts);
    return PyLong_FromSsize_t(n);
}

#define HELD_ROWS_DOC                                                                              \
    "held_rows(params, ideal_block, chain_block, target, values, free, keep_tol, fold_margin, "   \
    "out, counts) -> rows written: an idealised form's branches at the held joint's values, "     \
    "polished on the true chain with that joint fixed (see kin/_native/ik/analytic/seven_r/_held7.h)."

#endif

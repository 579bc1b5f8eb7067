/*
 * Every branch of a 7R free-joint closed form over a grid of free-joint values in one call: the
 * compiled twin of kin/ik/numeric/all_branches.py's path (kin/ik/analytic/seven_r/branches7.py:
 * branches_over, distinct, windings; the judge's errors by the table's DH product, chain_pose7).
 * The same steps in the same order, so the same branches in the same order: the Python path is
 * the reference and the fallback (tests/native/test_all_branches_twin.py holds the two to it).
 * Included by _closed7.c and _shoulder7.c after _seeded7.h, which need
 *   static int branches_at_value(const Params *P, const double *T, double value,
 *                                double (*sol)[7]);
 * the branches (up to 8, joints wrapped into [-pi, pi], limits ignored: P is the form of the
 * arm without limits) at one free-joint value of the prepared target T (prepare_seeded, mode 0).
 * Angles in radians, lengths in meters.
 *
 * all_branches(params, seed_block, target, values, lower, upper, near, position_tol,
 *              rotation_tol, near_miss, solution, empty)
 *   params:     bytes of the Params of the form without limits (joints in [-pi, pi]);
 *   seed_block: bytes of the Seed block (its chain: the judge's DH product, its frames);
 *   target:     a full pose (target_values in _twin.h);
 *   values:     float64[G], the free-joint values [rad];
 *   lower, upper, near: float64[7], the limits and the seed moved inside them [rad];
 *   position_tol, rotation_tol: the largest errors of a kept branch [m], [rad] (strictly below);
 *   near_miss:  a branch off by less than this in both (not within the tolerances) has the
 *               Python path polish it: the call answers None;
 *   solution:   the class IKSolution; empty: numpy.empty (the rows' array).
 *   Returns (solutions, rejected), tuples of IKSolution: the branches inside the limits within
 *   the tolerances, nearest `near` first, and the branches on target with no 2 pi copy inside
 *   the limits; or None (a near miss, a target that is not a finite pose): the Python path.
 *
 * sift_rows(seed_block, target, rows, lower, upper, near, position_tol, rotation_tol, near_miss,
 *           solution, empty): the same answer for branches already found (rows: float64[M, 7],
 *   limits ignored, no NaN row): the general 7R form's (General7RIK.branches_at, in NumPy),
 *   judged by the chain of a Seed block whose frames are unused (twin_support.chain_block).
 */
#ifndef KIN_IK_ANALYTIC_SEVEN_R_BRANCHES7_H
#define KIN_IK_ANALYTIC_SEVEN_R_BRANCHES7_H

#include <stdlib.h>

#define DISTINCT_TOL 1e-6 /* branches7.DISTINCT [rad] */
#define SPAN_TURNS 3.0    /* windings: limits spanning this many turns keep the value */

static int branches_at_value(const Params *P, const double *T, double value, double (*sol)[7]);

/* np.mod(x, 2 pi): in [0, 2 pi) (Python's sign convention). */
static inline double mod_turn(double x)
{
    double m = fmod(x, TWO_PI);
    if (m != 0.0 && m < 0.0) m += TWO_PI;
    return m;
}

typedef struct {
    double key;
    Py_ssize_t index;
} Keyed;

/* Whether x comes before y: ascending key, then index (a strict order: the same result as a
   stable sort by key). */
static inline int keyed_before(const Keyed *x, const Keyed *y)
{
    return x->key < y->key || (x->key == y->key && x->index < y->index);
}

/* Sort n items of `size` bytes, each starting with a Keyed, by keyed_before: Shell's sort with
   Ciura's gaps, the comparison inline (qsort's call per comparison and buffer cost more here,
   a few hundred rows). */
static void keyed_sort(void *items, Py_ssize_t n, size_t size)
{
    static const Py_ssize_t gaps[] = {701, 301, 132, 57, 23, 10, 4, 1};
    char *base = items, hold[sizeof(double) * 16];
    if (size > sizeof hold) return; /* not reached: Keyed and Kept fit */
    for (size_t g = 0; g < sizeof gaps / sizeof gaps[0]; g++) {
        Py_ssize_t gap = gaps[g];
        for (Py_ssize_t i = gap; i < n; i++) {
            memcpy(hold, base + (size_t)i * size, size);
            Py_ssize_t j = i;
            while (j >= gap && keyed_before((const Keyed *)hold,
                                            (const Keyed *)(base + (size_t)(j - gap) * size))) {
                memcpy(base + (size_t)j * size, base + (size_t)(j - gap) * size, size);
                j -= gap;
            }
            memcpy(base + (size_t)j * size, hold, size);
        }
    }
}

/* branches7.distinct: rows (n of 7) without those equal to an earlier one modulo a turn within
   tol, order kept (compacted in place); returns how many remain, -1 when out of memory. */
static Py_ssize_t distinct_rows(double (*rows)[7], Py_ssize_t n, double tol)
{
    if (n < 2) return n;
    Keyed *order = malloc((size_t)n * sizeof *order);
    char *duplicate = calloc((size_t)n, 1);
    if (order == NULL || duplicate == NULL) {
        free(order);
        free(duplicate);
        return -1;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        order[i].key = mod_turn(rows[i][0]);
        order[i].index = i;
    }
    keyed_sort(order, n, sizeof *order);
    for (Py_ssize_t i = 0; i < n; i++) {
        for (Py_ssize_t offset = 1; offset < n; offset++) {
            Py_ssize_t j = (i + offset) % n;
            if (!(mod_turn(order[j].key - order[i].key) < tol)) break;
            const double *a = rows[order[i].index], *b = rows[order[j].index];
            double worst = 0.0;
            for (int k = 0; k < 7; k++) {
                double gap = a[k] - b[k];
                double e = fabs(gap - TWO_PI * nearbyint(gap / TWO_PI));
                worst = e > worst ? e : worst;
            }
            if (worst < tol) {
                Py_ssize_t later = order[i].index > order[j].index ? order[i].index : order[j].index;
                duplicate[later] = 1;
            }
        }
    }
    Py_ssize_t kept = 0;
    for (Py_ssize_t i = 0; i < n; i++)
        if (!duplicate[i]) {
            if (kept != i) memcpy(rows[kept], rows[i], sizeof rows[i]);
            kept++;
        }
    free(order);
    free(duplicate);
    return kept;
}

/* branches7.windings of one row: the values (up to `most` each) of joint j inside its limits,
   counts[j] of them into options[j]; 0 when a joint has none. */
static int winding_options(const double *row, const double *lo, const double *hi, int most,
                           double (*options)[8], int *counts)
{
    for (int j = 0; j < 7; j++) {
        double low = lo[j], high = hi[j], v = row[j];
        counts[j] = 0;
        if (!(high - low < TWO_PI * SPAN_TURNS)) { /* unlimited: the value as it is */
            options[j][counts[j]++] = v;
            continue;
        }
        double first = ceil((low - v) / TWO_PI);
        double count = floor((high - v) / TWO_PI) - first + 1.0;
        if (!isfinite(count) || count < 0.0) count = 0.0;
        for (int k = 0; k < (int)count && counts[j] < most; k++) {
            double copy = v + TWO_PI * (first + (double)k);
            if (low <= copy && copy <= high) options[j][counts[j]++] = copy;
        }
        if (counts[j] == 0) return 0;
    }
    return 1;
}

/* The judge's errors of the table's pose at q against p, r. */
static inline void branch_errors(const Seed *S, const double *q, const double *p, const double *r,
                                 double *errors)
{
    double pose[12];
    chain_pose7(S, q, pose);
    pose_errors(pose, p, r, &errors[0], &errors[1]);
}

/* A row (7 joints, then the position and rotation errors), ordered by its squared distance to
   the seed (order.key), then its place (order.index): sorted by keyed_sort. */
typedef struct {
    Keyed order;
    double q[9];
} Kept;

/* Whether the copy one->q of the row (q, errors) is inside the limits and within the
   tolerances: its errors (the row's when it is the row itself) and squared distance to near. */
static int copy_kept(const Seed *S, const double *row, Kept *one, const double *p, const double *r,
                     const double *lo, const double *hi, const double *near, const double *tol)
{
    for (int j = 0; j < 7; j++)
        if (!(lo[j] <= one->q[j] && one->q[j] <= hi[j])) return 0;
    if (memcmp(one->q, row, 7 * sizeof(double)) == 0)
        memcpy(one->q + 7, row + 7, 2 * sizeof(double));
    else
        branch_errors(S, one->q, p, r, one->q + 7);
    if (!(one->q[7] < tol[0] && one->q[8] < tol[1])) return 0;
    one->order.key = 0.0;
    for (int j = 0; j < 7; j++) one->order.key += (one->q[j] - near[j]) * (one->q[j] - near[j]);
    return 1;
}

/* A tuple of IKSolution (cls) of the n rows (q, then the two errors), within_limits `inside`:
   their q rows of one new (n, 7) array made by empty. */
static PyObject *solutions_of(PyObject *cls, PyObject *empty, const double *rows, Py_ssize_t stride,
                              Py_ssize_t n, int inside)
{
    PyObject *array = PyObject_CallFunction(empty, "((nn))", n, (Py_ssize_t)7);
    if (array == NULL) return NULL;
    Py_buffer view;
    if (PyObject_GetBuffer(array, &view, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE) < 0) {
        Py_DECREF(array);
        return NULL;
    }
    double *out = view.buf;
    for (Py_ssize_t k = 0; k < n; k++) memcpy(out + 7 * k, rows + stride * k, 7 * sizeof(double));
    PyBuffer_Release(&view);
    PyObject *tuple = PyTuple_New(n);
    for (Py_ssize_t k = 0; tuple != NULL && k < n; k++) {
        const double *row = rows + stride * k;
        PyObject *one = make_solution((PyTypeObject *)cls, PySequence_GetItem(array, k),
                                      empty_label, inside, row[7], row[8]);
        if (one == NULL) Py_CLEAR(tuple);
        else PyTuple_SET_ITEM(tuple, k, one);
    }
    Py_DECREF(array);
    return tuple;
}

/* The pipeline on the distinct rows (n of 7); answers as all_branches (None: Py_None). */
static PyObject *sift_branches(const Seed *S, double (*rows)[7], Py_ssize_t n, const double *p,
                               const double *r, const double *lo, const double *hi,
                               const double *near, const double *tol, double near_miss,
                               PyObject *cls, PyObject *empty)
{
    /* on target: rows, their errors; a near miss goes the Python way */
    double (*on)[9] = malloc((size_t)(n ? n : 1) * sizeof *on);
    if (on == NULL) return PyErr_NoMemory();
    Py_ssize_t m = 0;
    for (Py_ssize_t i = 0; i < n; i++) {
        double e[2];
        branch_errors(S, rows[i], p, r, e);
        if (e[0] < tol[0] && e[1] < tol[1]) {
            memcpy(on[m], rows[i], 7 * sizeof(double));
            on[m][7] = e[0];
            on[m][8] = e[1];
            m++;
        } else if (e[0] < near_miss && e[1] < near_miss) {
            free(on);
            Py_RETURN_NONE;
        }
    }
    /* windings: every copy inside the limits, measured again; rows without one are rejected */
    Py_ssize_t capacity = 16, count = 0, outside = 0;
    Kept *kept = malloc((size_t)capacity * sizeof *kept);
    double (*rejected)[9] = malloc((size_t)(m ? m : 1) * sizeof *rejected);
    if (kept == NULL || rejected == NULL) {
        free(on);
        free(kept);
        free(rejected);
        return PyErr_NoMemory();
    }
    for (Py_ssize_t i = 0; i < m; i++) {
        double options[7][8];
        int counts[7], index[7] = {0};
        if (!winding_options(on[i], lo, hi, 8, options, counts)) {
            memcpy(rejected[outside++], on[i], sizeof on[i]);
            continue;
        }
        for (;;) { /* joint 0 outermost, as windings() expands joint by joint */
            Kept one;
            for (int j = 0; j < 7; j++) one.q[j] = options[j][index[j]];
            if (copy_kept(S, on[i], &one, p, r, lo, hi, near, tol)) {
                one.order.index = count;
                if (count == capacity) {
                    Kept *more = realloc(kept, (size_t)(capacity *= 2) * sizeof *kept);
                    if (more == NULL) {
                        free(on);
                        free(kept);
                        free(rejected);
                        return PyErr_NoMemory();
                    }
                    kept = more;
                }
                kept[count++] = one;
            }
            int j = 6;
            while (j >= 0 && ++index[j] == counts[j]) index[j--] = 0;
            if (j < 0) break;
        }
    }
    free(on);
    keyed_sort(kept, count, sizeof *kept); /* Kept starts with its Keyed */
    PyObject *answer = NULL, *good = solutions_of(cls, empty, kept[0].q, sizeof *kept / sizeof(double), count, 1);
    PyObject *bad = good == NULL ? NULL : solutions_of(cls, empty, rejected[0], 9, outside, 0);
    if (bad != NULL) answer = PyTuple_Pack(2, good, bad);
    Py_XDECREF(good);
    Py_XDECREF(bad);
    free(kept);
    free(rejected);
    return answer;
}

/* What all_branches and sift_rows both read: the chain, the target, the limits and the seed, the
   tolerances, the classes. */
typedef struct {
    Seed S;
    double p[3], r[9], lo[7], hi[7], near[7], tol[2], near_miss;
    PyObject *cls, *empty;
} Sift;

/* Sift of block (bytes of a Seed) and rest = target, (skipped), lower, upper, near, position_tol,
   rotation_tol, near_miss, solution, empty: 1; 0 with an error; -1 when the target is not a
   finite pose (the Python path). */
static int sift_args(PyObject *block, PyObject *const *rest, Sift *s)
{
    if (!PyBytes_Check(block) || PyBytes_GET_SIZE(block) != sizeof s->S || !PyType_Check(rest[8]) ||
        !PyCallable_Check(rest[9])) {
        PyErr_SetString(PyExc_ValueError, "seed_block: bytes of the block; solution: a class; "
                                          "empty: a callable");
        return 0;
    }
    memcpy(&s->S, PyBytes_AS_STRING(block), sizeof s->S);
    s->tol[0] = PyFloat_AsDouble(rest[5]);
    s->tol[1] = PyFloat_AsDouble(rest[6]);
    s->near_miss = PyFloat_AsDouble(rest[7]);
    if (PyErr_Occurred()) return 0;
    if (!copy_doubles(rest[2], 7, s->lo) || !copy_doubles(rest[3], 7, s->hi) ||
        !copy_doubles(rest[4], 7, s->near)) {
        PyErr_SetString(PyExc_ValueError, "lower, upper, near: float64[7]");
        return 0;
    }
    s->cls = rest[8];
    s->empty = rest[9];
    if (target_values(rest[0], s->p, s->r) != 0) return -1;
    return all_finite(s->p, 3) && all_finite(s->r, 9) ? 1 : -1;
}

/* The answer of the n rows (freed here): distinct, then sift_branches. */
static PyObject *sift_answer(const Sift *s, double (*rows)[7], Py_ssize_t n)
{
    n = distinct_rows(rows, n, DISTINCT_TOL);
    PyObject *answer = n < 0 ? PyErr_NoMemory()
                             : sift_branches(&s->S, rows, n, s->p, s->r, s->lo, s->hi, s->near,
                                             s->tol, s->near_miss, s->cls, s->empty);
    free(rows);
    return answer;
}

static PyObject *all_branches(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 12) {
        PyErr_SetString(PyExc_TypeError,
                        "all_branches(params, seed_block, target, values, lower, upper, near, "
                        "position_tol, rotation_tol, near_miss, solution, empty)");
        return NULL;
    }
    Params P;
    Sift s;
    if (!PyBytes_Check(args[0]) || PyBytes_GET_SIZE(args[0]) != sizeof P) {
        PyErr_SetString(PyExc_ValueError, "params: bytes of the block");
        return NULL;
    }
    memcpy(&P, PyBytes_AS_STRING(args[0]), sizeof P);
    int taken = sift_args(args[1], args + 2, &s);
    if (taken <= 0) return taken < 0 ? Py_NewRef(Py_None) : NULL;
    Py_buffer values;
    if (!get_doubles(args[3], &values, 0, "values")) return NULL;
    Py_ssize_t g = values.len / (Py_ssize_t)sizeof(double), n = 0;
    double (*rows)[7] = malloc((size_t)(g ? g : 1) * 8 * sizeof *rows);
    if (rows == NULL) {
        PyBuffer_Release(&values);
        return PyErr_NoMemory();
    }
    double T[12];
    prepare_seeded(&s.S, 0, s.p, s.r, T);
    const double *grid = values.buf;
    for (Py_ssize_t k = 0; k < g; k++) {
        double sol[8][7];
        int found = branches_at_value(&P, T, grid[k], sol);
        for (int b = 0; b < found; b++)
            if (all_finite(sol[b], 7)) memcpy(rows[n++], sol[b], sizeof sol[b]);
    }
    PyBuffer_Release(&values);
    return sift_answer(&s, rows, n);
}

/* sift_rows(seed_block, target, rows, lower, upper, near, position_tol, rotation_tol, near_miss,
   solution, empty): all_branches's answer for branches already found (rows: float64[M, 7], any
   form's branches_at without its NaN rows), the Seed block's chain as the judge. */
static PyObject *sift_rows(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 11) {
        PyErr_SetString(PyExc_TypeError,
                        "sift_rows(seed_block, target, rows, lower, upper, near, position_tol, "
                        "rotation_tol, near_miss, solution, empty)");
        return NULL;
    }
    Sift s;
    int taken = sift_args(args[0], args + 1, &s);
    if (taken <= 0) return taken < 0 ? Py_NewRef(Py_None) : NULL;
    Py_buffer view;
    if (!get_doubles(args[2], &view, 0, "rows")) return NULL;
    Py_ssize_t n = view.len / (Py_ssize_t)(7 * sizeof(double));
    double (*rows)[7] = malloc((size_t)(n ? n : 1) * sizeof *rows);
    if (rows != NULL) memcpy(rows, view.buf, (size_t)n * sizeof *rows);
    PyBuffer_Release(&view);
    if (rows == NULL) return PyErr_NoMemory();
    return sift_answer(&s, rows, n);
}

#define ALL_BRANCHES_DOC                                                                         \
    "all_branches(params, seed_block, target, values, lower, upper, near, position_tol, "         \
    "rotation_tol, near_miss, solution, empty) -> (solutions, rejected) or None: every branch at " \
    "the free-joint values, verified, nearest `near` first (see kin/_native/ik/analytic/seven_r/_branches7.h)."
#define SIFT_ROWS_DOC                                                                              \
    "sift_rows(seed_block, target, rows, lower, upper, near, position_tol, rotation_tol, "         \
    "near_miss, solution, empty) -> (solutions, rejected) or None: all_branches's answer for "     \
    "branches already found (see kin/_native/ik/analytic/seven_r/_branches7.h)."

#endif

/*
 * Compiled twin of kin/plan/sphere_motion.py (optional: without it the NumPy form runs, with the
 * same verdicts; tests/native/test_sphere_motion.py holds them to it). The motion rule of
 * kin/path/collision_check.py applied to spheres that enclose the arm's shapes: a state is shown
 * free when every test (a sphere against a sphere of another shape, or against a scene shape) is
 * farther apart than twice the contact tolerance; a straight joint motion when, for every test,
 * (d0 - tol) + (d1 - tol) > B, B the most the test's two centers can close along the motion (the
 * test's arms [m/rad] times |q1 - q0|), halved where it cannot tell. "Not shown" (0) is never
 * "in collision": the caller then asks the exact rule.
 *
 * The motion's midpoint is looked at first (a test at or below tol there refuses the motion, one
 * check, as the halving would at its first midpoint); each end of a segment is placed once and
 * each test's value at it computed once, when first read, whichever half reads it.
 *
 * Tests come in groups (one pair of shapes): a group's first test is a coarse one, of one sphere
 * enclosing each shape's cover; when it shows the motion free the group's other tests are skipped.
 *
 * make(parent, qidx, axis, placement, sphere_joint, sphere_center, test_a, test_b, test_k,
 *      test_arms, test_offset, group_start, shape_kind, shape_rotation, shape_center, shape_half)
 *   -> a capsule. Arrays: int32 / float64, C order (the Python side makes them so).
 * state(capsule, q, apart) -> bool: every test above ``apart`` [m] at q.
 * motion(capsule, q0, q1, tol, resolution, max_checks) -> (bool, checks).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_Q 32
#define MAX_DEPTH 60
/* Ends alive at once in motion(): one more than the segments on its stack. */
#define END_SLOTS (MAX_DEPTH + 4)

typedef struct {
    int nj, nq, ns, nt, ng, nk;
    int *parent, *qidx;      /* per joint */
    double *axis, *place;    /* per joint: (3), (12: rotation row-major, translation) */
    int *sjoint;             /* per sphere */
    double *scenter;         /* per sphere (3), in its joint's frame */
    int *ta, *tb, *tk;       /* per test: sphere a, sphere b (-1: a scene shape), shape k */
    double *tarms, *toff;    /* per test: (nq) arms [m/rad], offset (radii + padding) [m] */
    int *gstart;             /* ng + 1 */
    int *kkind;              /* per shape: 0 box, 1 sphere, 2 cylinder, 3 capsule */
    double *krot, *kcen, *khalf;
    double *oM;              /* scratch: nj * 12 */
    /* scratch of motion(): the ends of the segments on its stack (END_SLOTS of them), each
       end's sphere centers placed once and its test values computed when first read */
    double *end_centers;     /* END_SLOTS * ns * 3 */
    double *end_values;      /* END_SLOTS * nt */
    unsigned char *end_known; /* END_SLOTS * nt */
    int end_refs[MAX_DEPTH + 4], end_free[MAX_DEPTH + 4], end_nfree;
} Model;

static void model_free(Model *m)
{
    if (!m) return;
    free(m->parent); free(m->qidx); free(m->axis); free(m->place); free(m->sjoint);
    free(m->scenter); free(m->ta); free(m->tb); free(m->tk); free(m->tarms); free(m->toff);
    free(m->gstart); free(m->kkind); free(m->krot); free(m->kcen); free(m->khalf); free(m->oM);
    free(m->end_centers); free(m->end_values); free(m->end_known);
    free(m);
}

static void capsule_free(PyObject *cap)
{
    model_free((Model *)PyCapsule_GetPointer(cap, "kin.sphere_motion"));
}

/* A copy of a C-contiguous buffer of `count` items of `size` bytes (format d or i); NULL on error. */
static void *copy_array(PyObject *obj, Py_ssize_t count, Py_ssize_t size, const char *what)
{
    Py_buffer view;
    if (PyObject_GetBuffer(obj, &view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) return NULL;
    if (view.itemsize != size || view.len != count * size) {
        PyErr_Format(PyExc_ValueError, "sphere_motion.make: %s has the wrong size or type", what);
        PyBuffer_Release(&view);
        return NULL;
    }
    void *out = malloc(count * size > 0 ? (size_t)(count * size) : 1);
    if (!out) {
        PyBuffer_Release(&view);
        PyErr_NoMemory();
        return NULL;
    }
    memcpy(out, view.buf, (size_t)(count * size));
    PyBuffer_Release(&view);
    return out;
}

static Py_ssize_t length(PyObject *obj)
{
    Py_buffer view;
    if (PyObject_GetBuffer(obj, &view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) return -1;
    Py_ssize_t n = view.ndim ? view.shape[0] : 0;
    PyBuffer_Release(&view);
    return n;
}

static PyObject *make(PyObject *self, PyObject *args)
{
    PyObject *a[16];
    if (!PyArg_ParseTuple(args, "OOOOOOOOOOOOOOOO", &a[0], &a[1], &a[2], &a[3], &a[4], &a[5],
                          &a[6], &a[7], &a[8], &a[9], &a[10], &a[11], &a[12], &a[13], &a[14],
                          &a[15]))
        return NULL;
    Model *m = calloc(1, sizeof(Model));
    if (!m) return PyErr_NoMemory();
    Py_ssize_t nj = length(a[0]), ns = length(a[4]), nt = length(a[6]), ng1 = length(a[11]),
               nk = length(a[12]);
    if (nj < 1 || ns < 0 || nt < 0 || ng1 < 1 || nk < 0) {
        model_free(m);
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_ValueError, "sphere_motion.make: bad sizes");
        return NULL;
    }
    m->nj = (int)nj; m->ns = (int)ns; m->nt = (int)nt; m->ng = (int)ng1 - 1; m->nk = (int)nk;
    Py_ssize_t arms_len = length(a[9]);
    m->nq = nt > 0 ? 0 : 1;
    if ((m->parent = copy_array(a[0], nj, 4, "parent")) == NULL ||
        (m->qidx = copy_array(a[1], nj, 4, "qidx")) == NULL ||
        (m->axis = copy_array(a[2], nj * 3, 8, "axis")) == NULL ||
        (m->place = copy_array(a[3], nj * 12, 8, "placement")) == NULL ||
        (m->sjoint = copy_array(a[4], ns, 4, "sphere_joint")) == NULL ||
        (m->scenter = copy_array(a[5], ns * 3, 8, "sphere_center")) == NULL ||
        (m->ta = copy_array(a[6], nt, 4, "test_a")) == NULL ||
        (m->tb = copy_array(a[7], nt, 4, "test_b")) == NULL ||
        (m->tk = copy_array(a[8], nt, 4, "test_k")) == NULL ||
        (m->toff = copy_array(a[10], nt, 8, "test_offset")) == NULL ||
        (m->gstart = copy_array(a[11], ng1, 4, "group_start")) == NULL ||
        (m->kkind = copy_array(a[12], nk, 4, "shape_kind")) == NULL ||
        (m->krot = copy_array(a[13], nk * 9, 8, "shape_rotation")) == NULL ||
        (m->kcen = copy_array(a[14], nk * 3, 8, "shape_center")) == NULL ||
        (m->khalf = copy_array(a[15], nk * 3, 8, "shape_half")) == NULL) {
        model_free(m);
        return NULL;
    }
    /* nq: the largest joint index + 1 */
    int nq = 0;
    for (int j = 0; j < m->nj; j++)
        if (m->qidx[j] + 1 > nq) nq = m->qidx[j] + 1;
    m->nq = nq;
    if (nq > MAX_Q || arms_len != nt) {
        model_free(m);
        PyErr_SetString(PyExc_ValueError, "sphere_motion.make: too many joints or bad arms");
        return NULL;
    }
    if ((m->tarms = copy_array(a[9], nt * nq, 8, "test_arms")) == NULL) {
        model_free(m);
        return NULL;
    }
    m->oM = malloc(sizeof(double) * 12 * (size_t)nj);
    m->end_centers = malloc(sizeof(double) * 3 * (size_t)(ns + 1) * END_SLOTS);
    m->end_values = malloc(sizeof(double) * (size_t)(nt + 1) * END_SLOTS);
    m->end_known = malloc((size_t)(nt + 1) * END_SLOTS);
    if (!m->oM || !m->end_centers || !m->end_values || !m->end_known) {
        model_free(m);
        return PyErr_NoMemory();
    }
    PyObject *cap = PyCapsule_New(m, "kin.sphere_motion", capsule_free);
    if (!cap) model_free(m);
    return cap;
}

/* The joints' world placements at q into m->oM (rotation row-major, translation), then every
   sphere's center into centers (ns * 3). */
static void place(Model *m, const double *q, double *centers)
{
    double *oM = m->oM;
    /* joint 0: the world */
    memset(oM, 0, sizeof(double) * 12);
    oM[0] = oM[4] = oM[8] = 1.0;
    for (int j = 1; j < m->nj; j++) {
        const double *P = m->place + 12 * j, *A = oM + 12 * m->parent[j];
        double L[12]; /* parent * placement */
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                L[3 * r + c] = A[3 * r] * P[c] + A[3 * r + 1] * P[3 + c] + A[3 * r + 2] * P[6 + c];
            L[9 + r] = A[3 * r] * P[9] + A[3 * r + 1] * P[10] + A[3 * r + 2] * P[11] + A[9 + r];
        }
        double *O = oM + 12 * j;
        if (m->qidx[j] < 0) {
            memcpy(O, L, sizeof(L));
            continue;
        }
        /* Rodrigues: rotation by angle q about the unit axis (in the joint's frame) */
        const double *u = m->axis + 3 * j;
        double t = q[m->qidx[j]], s = sin(t), c = cos(t), v = 1.0 - c;
        double R[9] = {c + u[0] * u[0] * v,        u[0] * u[1] * v - u[2] * s, u[0] * u[2] * v + u[1] * s,
                       u[1] * u[0] * v + u[2] * s, c + u[1] * u[1] * v,        u[1] * u[2] * v - u[0] * s,
                       u[2] * u[0] * v - u[1] * s, u[2] * u[1] * v + u[0] * s, c + u[2] * u[2] * v};
        for (int r = 0; r < 3; r++)
            for (int cc = 0; cc < 3; cc++)
                O[3 * r + cc] = L[3 * r] * R[cc] + L[3 * r + 1] * R[3 + cc] + L[3 * r + 2] * R[6 + cc];
        O[9] = L[9]; O[10] = L[10]; O[11] = L[11];
    }
    for (int s = 0; s < m->ns; s++) {
        const double *O = oM + 12 * m->sjoint[s], *p = m->scenter + 3 * s;
        for (int r = 0; r < 3; r++)
            centers[3 * s + r] = O[3 * r] * p[0] + O[3 * r + 1] * p[1] + O[3 * r + 2] * p[2] + O[9 + r];
    }
}

/* Signed distance from the world point p to scene shape k [m] (negative inside). */
static double shape_distance(const Model *m, int k, const double *p)
{
    const double *R = m->krot + 9 * k, *c = m->kcen + 3 * k, *h = m->khalf + 3 * k;
    double d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]}, x[3];
    for (int i = 0; i < 3; i++) x[i] = R[i] * d[0] + R[3 + i] * d[1] + R[6 + i] * d[2]; /* R^T d */
    switch (m->kkind[k]) {
    case 0: { /* box */
        double out = 0.0, inside = -INFINITY;
        for (int i = 0; i < 3; i++) {
            double b = fabs(x[i]) - h[i];
            if (b > 0.0) out += b * b;
            if (b > inside) inside = b;
        }
        return sqrt(out) + (inside < 0.0 ? inside : 0.0);
    }
    case 1: /* sphere */
        return sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) - h[0];
    case 2: { /* cylinder along z */
        double radial = hypot(x[0], x[1]) - h[0], axial = fabs(x[2]) - h[1];
        double out = hypot(radial > 0.0 ? radial : 0.0, axial > 0.0 ? axial : 0.0);
        double in = radial > axial ? radial : axial;
        return out + (in < 0.0 ? in : 0.0);
    }
    default: { /* capsule: the distance to its segment less its radius */
        double z = x[2] > h[1] ? x[2] - h[1] : (x[2] < -h[1] ? x[2] + h[1] : 0.0);
        return sqrt(x[0] * x[0] + x[1] * x[1] + z * z) - h[0];
    }
    }
}

/* Test t's lower bound at the centers [m]. */
static double test_distance(const Model *m, int t, const double *centers)
{
    const double *a = centers + 3 * m->ta[t];
    if (m->tb[t] >= 0) {
        const double *b = centers + 3 * m->tb[t];
        double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
        return sqrt(dx * dx + dy * dy + dz * dz) - m->toff[t];
    }
    return shape_distance(m, m->tk[t], a) - m->toff[t];
}

static double test_motion(const Model *m, int t, const double *dq)
{
    const double *arms = m->tarms + (size_t)m->nq * t;
    double b = 0.0;
    for (int i = 0; i < m->nq; i++) b += arms[i] * dq[i];
    return b;
}

static int read_q(PyObject *obj, int nq, double *out)
{
    Py_buffer view;
    if (PyObject_GetBuffer(obj, &view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) return 0;
    int ok = view.itemsize == 8 && view.len == 8 * nq && view.format && strcmp(view.format, "d") == 0;
    if (ok) memcpy(out, view.buf, 8 * (size_t)nq);
    PyBuffer_Release(&view);
    if (!ok) PyErr_SetString(PyExc_ValueError, "sphere_motion: q must be float64 of the arm's size");
    return ok;
}

typedef struct {
    double qa[MAX_Q], qb[MAX_Q];
    int ea, eb; /* the ends' slots (Model.end_*) */
    int *open;  /* groups still open on this segment */
    int count;
} Segment;

/* A slot for the end q (its centers placed, no test value known yet), held `refs` times. */
static int end_new(Model *m, const double *q, int refs)
{
    int e = m->end_free[--m->end_nfree];
    place(m, q, m->end_centers + (size_t)e * 3 * (m->ns + 1));
    memset(m->end_known + (size_t)e * (m->nt + 1), 0, (size_t)m->nt + 1);
    m->end_refs[e] = refs;
    return e;
}

static void end_release(Model *m, int e)
{
    if (--m->end_refs[e] == 0) m->end_free[m->end_nfree++] = e;
}

/* Test t's value at end e, computed once per end. */
static double end_value(Model *m, int e, int t)
{
    size_t at = (size_t)e * (m->nt + 1) + t;
    if (!m->end_known[at]) {
        m->end_values[at] = test_distance(m, t, m->end_centers + (size_t)e * 3 * (m->ns + 1));
        m->end_known[at] = 1;
    }
    return m->end_values[at];
}

/* Whether every group is above `apart` at end e: its coarse test, else every other test of it. */
static int end_apart(Model *m, int e, double apart)
{
    for (int g = 0; g < m->ng; g++) {
        int first = m->gstart[g], end = m->gstart[g + 1];
        if (end_value(m, e, first) > apart) continue;
        for (int t = first + 1; t < end; t++)
            if (!(end_value(m, e, t) > apart)) return 0;
    }
    return 1;
}

static void ends_reset(Model *m)
{
    m->end_nfree = END_SLOTS;
    for (int e = 0; e < END_SLOTS; e++) m->end_free[e] = END_SLOTS - 1 - e;
}

static PyObject *state(PyObject *self, PyObject *args)
{
    PyObject *cap, *qo;
    double apart;
    if (!PyArg_ParseTuple(args, "OOd", &cap, &qo, &apart)) return NULL;
    Model *m = PyCapsule_GetPointer(cap, "kin.sphere_motion");
    if (!m) return NULL;
    double q[MAX_Q];
    if (!read_q(qo, m->nq, q)) return NULL;
    ends_reset(m);
    return PyBool_FromLong(end_apart(m, end_new(m, q, 1), apart));
}

/* Whether test t shows the segment: 1 yes, 0 no (halve), -1 never (an end not apart, or the
   bound below the resolution). */
static int shows(Model *m, int t, int ea, int eb, const double *dq, double tol,
                 double resolution)
{
    double da = end_value(m, ea, t), db = end_value(m, eb, t);
    double bound = test_motion(m, t, dq);
    if ((da - tol) + (db - tol) > bound) return 1;
    if (!(da > tol) || !(db > tol) || bound <= resolution) return -1;
    return 0;
}

static PyObject *motion(PyObject *self, PyObject *args)
{
    PyObject *cap, *q0o, *q1o;
    double tol, resolution;
    long max_checks;
    if (!PyArg_ParseTuple(args, "OOOddl", &cap, &q0o, &q1o, &tol, &resolution, &max_checks))
        return NULL;
    Model *m = PyCapsule_GetPointer(cap, "kin.sphere_motion");
    if (!m) return NULL;
    int nq = m->nq, ng = m->ng;
    Segment *stack = malloc(sizeof(Segment) * (MAX_DEPTH + 2));
    int *lists = malloc(sizeof(int) * (size_t)(ng + 1) * (MAX_DEPTH + 2));
    if (!stack || !lists) {
        free(stack); free(lists);
        return PyErr_NoMemory();
    }
    for (int i = 0; i < MAX_DEPTH + 2; i++) stack[i].open = lists + (size_t)(ng + 1) * i;
    if (!read_q(q0o, nq, stack[0].qa) || !read_q(q1o, nq, stack[0].qb)) {
        free(stack); free(lists);
        return NULL;
    }
    ends_reset(m);
    /* the midpoint first: a test at or below tol there refuses the motion at once, one check
       (as the halving would at its first midpoint); else its values serve the first halving */
    int top = 1, verdict = 1, first_mid = -1;
    long checks = 0;
    double qm0[MAX_Q];
    for (int i = 0; i < nq; i++) qm0[i] = 0.5 * (stack[0].qa[i] + stack[0].qb[i]);
    if (max_checks >= 1) {
        first_mid = end_new(m, qm0, 1);
        if (!end_apart(m, first_mid, tol)) {
            free(stack); free(lists);
            return Py_BuildValue("(Nl)", PyBool_FromLong(0), 1L);
        }
    }
    stack[0].ea = end_new(m, stack[0].qa, 1);
    stack[0].eb = end_new(m, stack[0].qb, 1);
    for (int g = 0; g < ng; g++) stack[0].open[g] = g;
    stack[0].count = ng;
    while (top > 0 && verdict == 1) {
        Segment *seg = &stack[--top];
        double dq[MAX_Q];
        for (int i = 0; i < nq; i++) dq[i] = fabs(seg->qb[i] - seg->qa[i]);
        int kept = 0;
        for (int n = 0; n < seg->count && verdict == 1; n++) {
            int g = seg->open[n], first = m->gstart[g], end = m->gstart[g + 1];
            int coarse = shows(m, first, seg->ea, seg->eb, dq, tol, resolution);
            if (coarse == 1) continue;
            int open = 0;
            for (int t = first + 1; t < end; t++) {
                int found = shows(m, t, seg->ea, seg->eb, dq, tol, resolution);
                if (found == -1) {
                    verdict = 0;
                    break;
                }
                if (found == 0) open = 1;
            }
            if (open) seg->open[kept++] = g;
        }
        if (verdict != 1 || kept == 0) {
            end_release(m, seg->ea);
            end_release(m, seg->eb);
            continue;
        }
        if (top + 2 > MAX_DEPTH || checks >= max_checks) {
            verdict = 0;
            break;
        }
        checks++;
        /* the halves: the later one below the earlier one on the stack; both inherit the open
           groups (the segment's own list is copied before its slot is reused) */
        Segment *later = &stack[top + 1], *earlier = &stack[top];
        double qm[MAX_Q];
        for (int i = 0; i < nq; i++) qm[i] = 0.5 * (seg->qa[i] + seg->qb[i]);
        /* the midpoint: one end of each half (its values computed once, read by both) */
        int em;
        if (first_mid >= 0) { /* the first halving: the midpoint looked at first */
            em = first_mid;
            m->end_refs[em] = 2;
            first_mid = -1;
        } else {
            em = end_new(m, qm, 2);
        }
        /* seg is stack[top] (just popped): write the later half into top + 1 first */
        memcpy(later->qa, qm, sizeof(double) * nq);
        memcpy(later->qb, seg->qb, sizeof(double) * nq);
        later->ea = em;
        later->eb = seg->eb;
        memcpy(later->open, seg->open, sizeof(int) * (size_t)kept);
        later->count = kept;
        /* earlier half in place: qa stays, qb becomes the midpoint, open list the same */
        memcpy(earlier->qb, qm, sizeof(double) * nq);
        earlier->eb = em;
        earlier->count = kept;
        /* order: pop the earlier first -> it must be on top: swap the two slots' roles */
        Segment tmp = stack[top];
        stack[top] = stack[top + 1];
        stack[top + 1] = tmp;
        top += 2;
    }
    free(stack); free(lists);
    return Py_BuildValue("(Nl)", PyBool_FromLong(verdict), checks);
}

static PyMethodDef methods[] = {
    {"make", make, METH_VARARGS, "make(...) -> capsule: the spheres, tests and scene of one model."},
    {"state", state, METH_VARARGS, "state(capsule, q, apart) -> every test above apart [m] at q."},
    {"motion", motion, METH_VARARGS,
     "motion(capsule, q0, q1, tol, resolution, max_checks) -> (shown free, midpoints checked)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_sphere_motion",
                                    "Compiled twin of kin/plan/sphere_motion.py.", -1, methods};

PyMODINIT_FUNC PyInit__sphere_motion(void) { return PyModule_Create(&module); }

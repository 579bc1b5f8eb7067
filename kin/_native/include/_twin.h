/*
 * What the compiled twins of the seven-joint closed forms share (_closed7.c, _shoulder7.c): the
 * parameter block declared once per twin from an X-macro list, its export as LAYOUT, the two
 * formulas both use (seven_r/subproblems.py: harmonic_roots, rotation_pair), the float64 buffer
 * check, the argument handling of the batched first_many and the module set-up. Angles in
 * radians, lengths in meters.
 */
#ifndef KIN_IK_ANALYTIC_TWIN_H
#define KIN_IK_ANALYTIC_TWIN_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#define COS_SLACK 1e-12
#define TWO_PI 6.283185307179586

/* One field of a parameter block: name, offset and size in float64 values. */
typedef struct {
    const char *name;
    Py_ssize_t offset, size;
} TwinField;

/*
 * TWIN_BLOCK(Type, LIST, Count, Fields) declares a parameter block from LIST(X) with
 * X(field, size, description): the struct Type (all doubles: no padding, so a float64[Count]
 * buffer is a Type, checked at compile time), the constant Count, and Fields, its layout
 * (exported by the modules). It needs Type##_ENTRY(field, size, description): TWIN_ENTRY_OF
 * for that type. TWIN_PARAMS(LIST) is the twin's own block: Params, PARAM_COUNT, FIELDS
 * (exported as LAYOUT).
 */
#define TWIN_FIELD(name, size, doc) double name[size];
#define TWIN_SIZE(name, size, doc) +(size)
#define TWIN_ENTRY_OF(Type, name, size) \
    {#name, (Py_ssize_t)(offsetof(Type, name) / sizeof(double)), (Py_ssize_t)(size)},
#define TWIN_BLOCK(Type, LIST, Count, Fields)                                                  \
    typedef struct {                                                                           \
        LIST(TWIN_FIELD)                                                                       \
    } Type;                                                                                    \
    enum { Count = 0 LIST(TWIN_SIZE) };                                                        \
    typedef char Type##_has_no_padding[sizeof(Type) == Count * sizeof(double) ? 1 : -1];      \
    static const TwinField Fields[] = {LIST(Type##_ENTRY)};
#define Params_ENTRY(name, size, doc) TWIN_ENTRY_OF(Params, name, size)
#define TWIN_PARAMS(LIST) TWIN_BLOCK(Params, LIST, PARAM_COUNT, FIELDS)

/* c into [-1, 1] when within COS_SLACK of it; 0 when further out (no angle). */
static inline int clamp_cos(double *c)
{
    if (*c > 1.0) {
        if (*c > 1.0 + COS_SLACK) return 0;
        *c = 1.0;
    } else if (*c < -1.0) {
        if (*c < -1.0 - COS_SLACK) return 0;
        *c = -1.0;
    }
    return 1;
}

/* seven_r/subproblems.harmonic_roots: angles t with p cos t + q sin t = k; returns how many (0 to 2). */
static inline int harmonic_roots(double p, double q, double k, double *t)
{
    double rho = hypot(p, q);
    if (rho < 1e-15) return 0;
    double c = k / rho;
    if (!clamp_cos(&c)) return 0;
    double phi = atan2(q, p), delta = acos(c);
    if (!(delta > 0.0)) {
        t[0] = phi;
        return 1;
    }
    t[0] = phi + delta;
    t[1] = phi - delta;
    return 2;
}

/* remainder(angle, TWO_PI), without the call where it returns angle itself: for |angle| <= pi
   the exact quotient is at most 1/2 in size, which rounds (to even) to 0. Bit for bit the same
   value (a NaN or an infinity goes to the call). */
static inline double turn_remainder(double angle)
{
    return fabs(angle) <= 0.5 * TWO_PI ? angle : remainder(angle, TWO_PI);
}

/* Whether some angle + 2 pi k [rad] lies within [lo, hi] widened by 1e-9 rad (always when the
   range spans a turn, or a limit is not finite): a test that never fails for an angle that a
   limit check (plain, or moving it by whole turns) would keep. */
static inline int may_fit(double angle, double lo, double hi)
{
    double half = 0.5 * (hi - lo);
    if (!(half < 0.5 * TWO_PI)) return 1;
    return fabs(turn_remainder(angle - 0.5 * (lo + hi))) <= half + 1e-9;
}

/* seven_r/subproblems.rotation_pair: (ta[i], tb[i]) with Rz(ta) Rx(alpha) Rz(tb) v = d
   (|v| = |d|), sa, ca = sin alpha, cos alpha, without the pairs whose tb - off_b fits no joint
   value in [lo_b, hi_b] (may_fit: the caller's limit check would drop them; their ta is not
   computed). The pairs kept are the Python function's, in its order, with the same arithmetic.
   cos tb[i], sin tb[i] go to cb[i], sb[i] (for a caller that needs them: the same values).
   Returns how many (0 to 2). */
static inline int rotation_pair_fit(double sa, double ca, const double *v, const double *d,
                                    double *ta, double *tb, double *cb_out, double *sb_out,
                                    double off_b, double lo_b, double hi_b)
{
    double roots[2];
    int n = harmonic_roots(sa * v[1], sa * v[0], d[2] - ca * v[2], roots), kept = 0;
    for (int i = 0; i < n; i++)
        if (may_fit(roots[i] - off_b, lo_b, hi_b)) tb[kept++] = roots[i];
    if (kept == 0) return 0;
    double heading = atan2(d[1], d[0]);
    for (int i = 0; i < kept; i++) {
        double cb = cos(tb[i]), sb = sin(tb[i]);
        cb_out[i] = cb;
        sb_out[i] = sb;
        double mx = v[0] * cb - v[1] * sb;
        double my = ca * (v[0] * sb + v[1] * cb) - sa * v[2];
        ta[i] = heading - atan2(my, mx);
    }
    return kept;
}

/*
 * Branches followed as directions (cos, sin) instead of angles: the scans' tests of whether a
 * free-joint value may have a branch inside the limits (q1_may_fit in _closed7.c,
 * branches_may_fit in _shoulder7.c). A test says "no" only beyond a slack that covers,
 * with a margin, the worst difference between a direction and the angle the exact path
 * computes, under these guards (an equation too weak, roots too near each other, a vector too
 * short to normalise: then the test says "maybe").
 */
#define ARC_SLACK 1e-6    /* joints solved by the first two equations of a branch */
#define CHAIN_SLACK 1e-3  /* the joints after them (through normalisations) */
#define ROOT_RHO_MIN 1e-2 /* [m] or [m^2]: weaker equations are not tested */
#define ROOT_EDGE 1e-3    /* |k / rho| beyond 1 - ROOT_EDGE: roots too near each other */
#define CHAIN_RHO_MIN 0.1 /* an arm whose later (constant) equation is weaker: not tested there */
#define SHORT_XY 1e-2     /* [m]: a shorter xy part of a vector is not normalised */
#define SHORT_UNIT 5e-2   /* the same for a unit vector's */
#define SHORT_MAX 1e100   /* nor a longer one (its square may overflow) */

/* cos, sin of the roots t of p cos t + q sin t = k (phi + delta, then phi - delta, as
   harmonic_roots orders them) into c, s: how many (0 or 2), or -1 when they are not to be
   trusted (or may be missing: within the slack of having roots). */
static inline int root_directions(double p, double q, double k, double *c, double *s)
{
    double rho = sqrt(p * p + q * q); /* not hypot: an overflow is refused below */
    if (!(rho >= ROOT_RHO_MIN && rho <= SHORT_MAX)) return -1;
    double inv = 1.0 / rho, x = k * inv;
    if (fabs(x) > 1.0 + ARC_SLACK) return 0;
    if (!(fabs(x) <= 1.0 - ROOT_EDGE)) return -1;
    double sd = sqrt((1.0 - x) * (1.0 + x)), cp = p * inv, sp = q * inv;
    c[0] = cp * x - sp * sd;
    s[0] = sp * x + cp * sd;
    c[1] = cp * x + sp * sd;
    s[1] = sp * x - cp * sd;
    return 2;
}

/* Whether the scans run these tests (1, as they do; 0 only to compare, in the tests, the answers
   with and without them: skips() below). Per module. */
static int directions_on = 1;

/* skips(on) -> the previous setting: whether the module's scans skip by directions. */
static inline PyObject *set_skips(PyObject *self, PyObject *arg)
{
    (void)self;
    int on = PyObject_IsTrue(arg);
    if (on < 0) return NULL;
    int previous = directions_on;
    directions_on = on;
    return PyBool_FromLong(previous);
}

#define SKIPS_DOC                                                                               \
    "skips(on) -> bool: whether scans skip the free-joint values where no branch, followed as " \
    "directions, fits the limits (the previous setting is returned). Only for comparing answers " \
    "with and without the skip; the answers are the same."

/* Whether the angle with direction (c, s) may be a joint's value within slack: its arc (cos, sin
   of the middle of its limits, as an angle t = q + offset; cos of half their span; 1 when the
   span is a turn or more, else 0: subproblems.limit_arcs). */
static inline int arc_admits(const double *arc, double c, double s, double slack)
{
    return arc[3] != 0.0 || c * arc[0] + s * arc[1] >= arc[2] - slack;
}

/* The direction of atan2(y0, x0) - atan2(y1, x1) into (c, s), or 0 when a vector is shorter
   than its guard. */
static inline int angle_difference(double x0, double y0, double short0, double x1, double y1,
                                   double short1, double *c, double *s)
{
    double n0 = sqrt(x0 * x0 + y0 * y0), n1 = sqrt(x1 * x1 + y1 * y1);
    if (!(n0 >= short0 && n1 >= short1 && n0 <= SHORT_MAX && n1 <= SHORT_MAX)) return 0;
    double inv = 1.0 / (n0 * n1);
    *c = (x0 * x1 + y0 * y1) * inv;
    *s = (y0 * x1 - x0 * y1) * inv;
    return 1;
}

/* The values of a C-contiguous float64 buffer of n values copied into out: 1, else 0 (no error). */
static inline int copy_doubles(PyObject *obj, Py_ssize_t n, double *out)
{
    Py_buffer view;
    if (PyObject_GetBuffer(obj, &view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) {
        PyErr_Clear();
        return 0;
    }
    int ok = view.len == n * (Py_ssize_t)sizeof(double) && view.itemsize == sizeof(double) &&
             view.format != NULL && strcmp(view.format, "d") == 0;
    if (ok) memcpy(out, view.buf, (size_t)n * sizeof(double));
    PyBuffer_Release(&view);
    return ok;
}

/* A target's position [m] into p and rotation (row-major) into r: from its packed values (a
   PoseTarget's _packed: bytes of the 12 float64) when it has them, else from its position and
   rotation (C-contiguous float64 arrays). Returns 0 for a pose, 1 for a position (rotation None),
   -1 when they cannot be read so (no error set: the caller takes the long way). */
static inline int target_values(PyObject *target, double *p, double *r)
{
    static PyObject *packed_name, *position_name, *rotation_name;
    if (packed_name == NULL) {
        packed_name = PyUnicode_InternFromString("_packed");
        position_name = PyUnicode_InternFromString("position");
        rotation_name = PyUnicode_InternFromString("rotation");
        if (rotation_name == NULL) {
            PyErr_Clear();
            return -1;
        }
    }
    PyObject *packed = PyObject_GetAttr(target, packed_name);
    if (packed == NULL) PyErr_Clear();
    if (packed != NULL && PyBytes_Check(packed) && PyBytes_GET_SIZE(packed) == 12 * sizeof(double)) {
        memcpy(p, PyBytes_AS_STRING(packed), 3 * sizeof(double));
        memcpy(r, PyBytes_AS_STRING(packed) + 3 * sizeof(double), 9 * sizeof(double));
        Py_DECREF(packed);
        return 0;
    }
    Py_XDECREF(packed);
    PyObject *position = PyObject_GetAttr(target, position_name);
    PyObject *rotation = position == NULL ? NULL : PyObject_GetAttr(target, rotation_name);
    int mode = -1;
    if (rotation == NULL)
        PyErr_Clear();
    else if (copy_doubles(position, 3, p))
        mode = rotation == Py_None ? 1 : (copy_doubles(rotation, 9, r) ? 0 : -1);
    Py_XDECREF(position);
    Py_XDECREF(rotation);
    return mode;
}

/*
 * A DH table's forward kinematics as written (the compiled checks' FK: a plain product of the
 * rows, independent of the closed forms' algebra; tests compare it with Pinocchio's). Poses are
 * 3x4 row-major (the last row 0 0 0 1 implied), lengths in meters, angles in radians.
 */

/* out = T A(t) for one row (a, cos alpha, sin alpha, d) at angle t = q + theta: each row of T
   times the row's transform written out (its zeros and ones skipped); modified: Craig's
   Rx(alpha) Tx(a) Rz(t) Tz(d), else Rz(t) Tz(d) Tx(a) Rx(alpha). Written straight to where it is
   kept (no copy of a matrix just written: reading it back whole before its stores land stalls). */
static inline void chain_step(int modified, double a, double ca, double sa, double d, double t,
                              const double *T, double *out)
{
    double ct = cos(t), st = sin(t);
    for (int i = 0; i < 3; i++) {
        const double *row = T + 4 * i;
        double r0 = row[0], r1 = row[1], r2 = row[2], r3 = row[3], *o = out + 4 * i;
        if (modified) {
            double u1 = ca * r1 + sa * r2, u2 = -sa * r1 + ca * r2;
            o[0] = ct * r0 + st * u1;
            o[1] = -st * r0 + ct * u1;
            o[2] = u2;
            o[3] = r3 + (a * r0 + d * u2);
        } else {
            double c0 = ct * r0 + st * r1, c1 = -st * r0 + ct * r1;
            o[0] = c0;
            o[1] = ca * c1 + sa * r2;
            o[2] = -sa * c1 + ca * r2;
            o[3] = r3 + (d * r2 + a * c0);
        }
    }
}

/* out = A B for 3x4 poses. */
static inline void chain_compose(const double *A, const double *B, double *out)
{
    for (int i = 0; i < 3; i++) {
        const double *row = A + 4 * i;
        for (int j = 0; j < 4; j++)
            out[4 * i + j] = row[0] * B[j] + row[1] * B[4 + j] + row[2] * B[8 + j];
        out[4 * i + 3] += row[3];
    }
}

/* The judge's errors of a 3x4 pose T against the target p [m], r (row-major): |p_T - p| [m] and
   the angle of R_T^T r from |R_T - r|_F = 2 sqrt(2) sin(angle / 2) [rad] (kin/ik/judge.py). */
static inline void pose_errors(const double *T, const double *p, const double *r,
                               double *position_error, double *rotation_error)
{
    double dx = T[3] - p[0], dy = T[7] - p[1], dz = T[11] - p[2], rotation2 = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double e = T[4 * i + j] - r[3 * i + j];
            rotation2 += e * e;
        }
    *position_error = sqrt(dx * dx + dy * dy + dz * dz);
    double half = sqrt(rotation2) / sqrt(8.0);
    *rotation_error = 2.0 * asin(1.0 < half ? 1.0 : half); /* NaN stays NaN */
}

/* A C-contiguous float64 buffer of obj in view; 0 and a Python error otherwise. */
static inline int get_doubles(PyObject *obj, Py_buffer *view, int writable, const char *name)
{
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0) return 0;
    if (view->format == NULL || strcmp(view->format, "d") != 0 || view->itemsize != sizeof(double)) {
        PyBuffer_Release(view);
        PyErr_Format(PyExc_TypeError, "%s: expected a C-contiguous float64 array", name);
        return 0;
    }
    return 1;
}

/* Buffers of objs[0 .. n-1] (get_doubles each, writable[i], named names[i]); on failure the ones
   already taken are released, 0 and a Python error. */
static inline int get_buffers(int n, PyObject *const *objs, Py_buffer *views, const int *writable,
                              const char *const *names)
{
    for (int i = 0; i < n; i++) {
        if (!get_doubles(objs[i], &views[i], writable[i], names[i])) {
            while (i-- > 0) PyBuffer_Release(&views[i]);
            return 0;
        }
    }
    return 1;
}

static inline void release_buffers(int n, Py_buffer *views)
{
    for (int i = 0; i < n; i++) PyBuffer_Release(&views[i]);
}

/* The shape check shared by the twins' first(): NULL when params, starts and out fit. */
static inline const char *check_arrays(const Py_buffer *params, Py_ssize_t count,
                                       const Py_buffer *starts, const Py_buffer *out)
{
    if (params->len != count * (Py_ssize_t)sizeof(double)) return "params: wrong size";
    if (starts->ndim != 2 || starts->shape[1] != 7) return "starts: not k x 7 float64";
    if (out->len != 7 * (Py_ssize_t)sizeof(double)) return "out: not 7 float64";
    return NULL;
}

/* The end of first(): the n buffers released, then ValueError(error) or the index found. */
static inline PyObject *first_result(int n, Py_buffer *views, const char *error, long found)
{
    release_buffers(n, views);
    if (error != NULL) {
        PyErr_SetString(PyExc_ValueError, error);
        return NULL;
    }
    return PyLong_FromLong(found);
}

/* A twin's first(): of the k starts Q (rows of 7), the first with a branch inside the limits for
   the prepared target T (mode 0: a pose, 12 values; 1: a position, 3), scanning by step; its
   branch into result and its index, or -1 (result untouched). */
typedef long (*FirstStart)(const void *params, int mode, const double *T, const double *Q,
                           Py_ssize_t k, double step, double *result);

/* A twin's first_many(params, [mode,] targets, starts, out, steps) -> count: the arguments
   checked (targets float64[N, 12] for a pose, mode 0, or [N, 3] for a position, mode 1; starts
   and out float64[N, 7]; steps float64[m]), then, without the GIL, first() of each target from
   its own start row, the steps in turn until one gives a branch: returns how many did. */
static inline PyObject *first_many_call(PyObject *args, int with_mode, Py_ssize_t count,
                                        FirstStart first)
{
    PyObject *objs[5];
    static const char *const names[5] = {"params", "targets", "starts", "out", "steps"};
    static const int writable[5] = {0, 0, 0, 1, 0};
    Py_buffer views[5];
    int mode = 0;
    int parsed = with_mode ? PyArg_ParseTuple(args, "OiOOOO", &objs[0], &mode, &objs[1], &objs[2],
                                              &objs[3], &objs[4])
                           : PyArg_ParseTuple(args, "OOOOO", &objs[0], &objs[1], &objs[2],
                                              &objs[3], &objs[4]);
    if (!parsed) return NULL;
    if (!get_buffers(5, objs, views, writable, names)) return NULL;
    Py_buffer *params = &views[0], *targets = &views[1], *starts = &views[2], *out = &views[3],
              *steps = &views[4];
    const char *error = NULL;
    Py_ssize_t width = mode == 1 ? 3 : 12, n = 0, found = 0;
    if (mode != 0 && mode != 1) error = "mode must be 0 (pose) or 1 (position)";
    else if (params->len != count * (Py_ssize_t)sizeof(double)) error = "params: wrong size";
    else if (targets->ndim != 2 || targets->shape[1] != width) error = "targets: not N x width float64";
    else if (starts->ndim != 2 || starts->shape[1] != 7 || starts->shape[0] != targets->shape[0])
        error = "starts: not N x 7 float64";
    else if (out->ndim != 2 || out->shape[1] != 7 || out->shape[0] != targets->shape[0])
        error = "out: not N x 7 float64";
    else if (steps->ndim != 1) error = "steps: not a float64 vector";
    if (error == NULL) {
        n = targets->shape[0];
        const double *T = targets->buf, *Q = starts->buf, *step = steps->buf;
        double *result = out->buf;
        Py_ssize_t n_steps = steps->shape[0];
        Py_BEGIN_ALLOW_THREADS
        for (Py_ssize_t i = 0; i < n; i++) {
            for (Py_ssize_t s = 0; s < n_steps; s++) {
                if (first(params->buf, mode, T + width * i, Q + 7 * i, 1, step[s], result + 7 * i) == 0) {
                    found++;
                    break;
                }
            }
        }
        Py_END_ALLOW_THREADS
    }
    release_buffers(5, views);
    if (error != NULL) {
        PyErr_SetString(PyExc_ValueError, error);
        return NULL;
    }
    return PyLong_FromSsize_t(found);
}

/* The docstring of first_many in the method tables. */
#define FIRST_MANY_DOC                                                                             \
    "first_many(params, [mode,] targets, starts, out, steps) -> how many targets got a branch: "   \
    "first() of each target row from its own start row, the scan steps in turn; out[i] receives " \
    "the rows found."

/* A start row q clipped into [lo, hi] joint by joint (7 values) into v; 0 when a value of q is
   not finite (the start is skipped). */
static inline int clip_start(const double *q, const double *lo, const double *hi, double *v)
{
    int finite = 1;
    for (int i = 0; i < 7; i++) {
        double x = q[i];
        finite = finite && isfinite(x);
        v[i] = x < lo[i] ? lo[i] : (x > hi[i] ? hi[i] : x);
    }
    return finite;
}

/* The first of the n branches sol nearest v (squared distance, 7 joints) copied to result. */
static inline void nearest(const double (*sol)[7], int n, const double *v, double *result)
{
    int best = 0;
    double best_d = INFINITY;
    for (int b = 0; b < n; b++) {
        double d = 0.0;
        for (int i = 0; i < 7; i++) d += (sol[b][i] - v[i]) * (sol[b][i] - v[i]);
        if (d < best_d) {
            best_d = d;
            best = b;
        }
    }
    memcpy(result, sol[best], 7 * sizeof(double));
}

/* A layout (((field, offset, size), ...) of fields) added to module m as name: 0, else -1. */
static inline int add_layout(PyObject *m, const char *name, const TwinField *fields, size_t n)
{
    PyObject *layout = PyTuple_New((Py_ssize_t)n);
    if (layout == NULL) return -1;
    for (size_t i = 0; i < n; i++) {
        PyObject *entry = Py_BuildValue("(snn)", fields[i].name, fields[i].offset, fields[i].size);
        if (entry == NULL) {
            Py_DECREF(layout);
            return -1;
        }
        PyTuple_SET_ITEM(layout, (Py_ssize_t)i, entry);
    }
    if (PyModule_AddObject(m, name, layout) < 0) {
        Py_DECREF(layout);
        return -1;
    }
    return 0;
}

/* The module of def with LAYOUT (((field, offset, size), ...) of fields) and PARAM_COUNT. */
static inline PyObject *twin_module(PyModuleDef *def, const TwinField *fields, size_t n,
                                    long count)
{
    PyObject *m = PyModule_Create(def);
    if (m == NULL) return NULL;
    if (add_layout(m, "LAYOUT", fields, n) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    if (PyModule_AddIntConstant(m, "PARAM_COUNT", count) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}

#endif

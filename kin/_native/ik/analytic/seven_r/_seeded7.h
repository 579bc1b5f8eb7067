/*
 * The seeded solve of a 7R free-joint closed form in one call (kin/ik/numeric/free_joint.py's
 * stage 0 from the caller's seed, the numeric pipeline's usual answer): the world target brought
 * to the structure's frames, first() from the seed for each scan step in turn, each branch found
 * measured by the table's DH product (chain_step in _twin.h, an FK independent of the closed
 * form's algebra; tests compare it with Pinocchio's). Included by _closed7.c and _shoulder7.c
 * after their Params, first_start and
 *   static void prepare_seeded(const Seed *S, int mode, const double *p, const double *r,
 *                              double *T);
 * which writes first_start's target T of a world pose (mode 0: p [m], r row-major) or point
 * (mode 1) through the frames of the Seed block, and SEEDED_POINTS (1 when first_start takes a
 * point, else 0: a position target is not taken).
 *
 * seeded(params, seed_block, steps, solution, result, name, message, method, clock, target,
 *        seed, position_tol, rotation_tol, start, out)
 *   params:     bytes of the structure's Params (its c_params);
 *   seed_block: bytes of a Seed (SEED_LAYOUT, kin.ik.numeric.free_joint.compiled_seeded);
 *   steps:      tuple of the scan steps [rad], tried in turn (0.0: the seed's free joint only);
 *   solution, result: the classes IKSolution and IKResult; name, message, method: the answer's
 *               solver, message and method (strings); clock: time.perf_counter;
 *   target:     its position [m] and R_world_tool in the world (or None: a position, mode 1),
 *               read by target_values (_twin.h);
 *   seed:       float64[7] [rad];
 *   start:      clock() at the call's start [s];
 *   out:        float64[7] receives the answer [rad] (the solution's q).
 *   Returns the IKResult of the answer (success, status "ok", one solution on out with its
 *   errors, 0 iterations, the time since start): the first step whose branch is within both
 *   tolerances (strictly below, as the judge); False when none is (the seed was tried: the
 *   pipeline goes on from the seed-table samples); None when the call does not take the target
 *   (a value that is not finite, a seed that is not 7 finite float64, a point beyond the reach
 *   bound): the pipeline from its start.
 */
#ifndef KIN_IK_ANALYTIC_SEVEN_R_SEEDED7_H
#define KIN_IK_ANALYTIC_SEVEN_R_SEEDED7_H

#include "_results.h"

/* X(field, size, description) */
#define SEED_PARAMS(X)                                                                  \
    X(modified, 1, "1 for a modified (Craig) table, 0 for a standard one")              \
    X(a, 7, "a of the table's rows [m]")                                                \
    X(cos_alpha, 7, "cos of the twists alpha")                                          \
    X(sin_alpha, 7, "sin of the twists alpha")                                          \
    X(d, 7, "d of the table's rows [m]")                                                \
    X(theta, 7, "theta offsets [rad]")                                                  \
    X(base, 12, "T_world_base, rows 0-2 of the 4x4, row-major [m]")                     \
    X(tool, 12, "T_last_tool, rows 0-2 of the 4x4, row-major [m]")                      \
    X(frame_r, 9, "K: rotation of the structure's base frame in the world, row-major")  \
    X(frame_t, 3, "k: its origin in the world [m]")                                     \
    X(end_r, 9, "M: rotation of the tool in the structure's last frame, row-major")     \
    X(end_t, 3, "m: its origin there [m]")                                              \
    X(point, 3, "a point of the structure's base frame its target needs [m]")           \
    X(reach, 4, "the table's base origin in the world [m], then the reach bound [m]")

#define Seed_ENTRY(name, size, doc) TWIN_ENTRY_OF(Seed, name, size)
TWIN_BLOCK(Seed, SEED_PARAMS, SEED_COUNT, SEED_FIELDS)

/* r = K^T R M^T (row-major) of a world rotation R. */
static inline void frame_rotation(const Seed *S, const double *R, double *r)
{
    const double *K = S->frame_r, *M = S->end_r;
    double a[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            a[3 * i + j] = K[i] * R[j] + K[3 + i] * R[3 + j] + K[6 + i] * R[6 + j];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r[3 * i + j] = a[3 * i] * M[3 * j] + a[3 * i + 1] * M[3 * j + 1] +
                           a[3 * i + 2] * M[3 * j + 2];
}

/* x = K^T (p - k) of a world point p [m]. */
static inline void frame_point(const Seed *S, const double *p, double *x)
{
    const double *K = S->frame_r, *k = S->frame_t;
    double v[3] = {p[0] - k[0], p[1] - k[1], p[2] - k[2]};
    for (int i = 0; i < 3; i++) x[i] = K[i] * v[0] + K[3 + i] * v[1] + K[6 + i] * v[2];
}

static void prepare_seeded(const Seed *S, int mode, const double *p, const double *r, double *T);

/* The tool pose of the table at q (7 joints) [rad], 3x4. */
static inline void chain_pose7(const Seed *S, const double *q, double *T)
{
    double a[12], b[12];
    const double *previous = S->base;
    const int modified = S->modified[0] != 0.0;
    for (int j = 0; j < 7; j++) {
        double *next = j % 2 ? b : a;
        chain_step(modified, S->a[j], S->cos_alpha[j], S->sin_alpha[j], S->d[j],
                   q[j] + S->theta[j], previous, next);
        previous = next;
    }
    chain_compose(previous, S->tool, T);
}

/* The IKResult of seeded()'s answer q with its errors (rotation NaN: a position target), q
   written to out (args as seeded's). */
static PyObject *seeded_result(PyObject *const *args, const double *q, double position_error,
                               double rotation_error, double start)
{
    PyObject *out = args[14];
    Py_buffer view;
    if (PyObject_GetBuffer(out, &view, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE | PyBUF_FORMAT) < 0)
        return NULL;
    int fits = view.len == 7 * (Py_ssize_t)sizeof(double) && view.format != NULL &&
               strcmp(view.format, "d") == 0;
    if (fits) memcpy(view.buf, q, 7 * sizeof(double));
    PyBuffer_Release(&view);
    if (!fits) {
        PyErr_SetString(PyExc_ValueError, "out: not 7 float64");
        return NULL;
    }
    Py_INCREF(out);
    PyObject *one = make_solution((PyTypeObject *)args[3], out, empty_label, 1, position_error,
                                  rotation_error);
    if (one == NULL) return NULL;
    PyObject *solutions = PyTuple_Pack(1, one);
    Py_DECREF(one);
    if (solutions == NULL) return NULL;
    PyObject *now = PyObject_CallNoArgs(args[8]);
    double elapsed = now == NULL ? -1.0 : PyFloat_AsDouble(now) - start;
    Py_XDECREF(now);
    PyObject *answer = NULL;
    if (!PyErr_Occurred())
        answer = make_success((PyTypeObject *)args[4], args[5], status_ok, args[6], solutions,
                              no_args, 0, elapsed, args[7]);
    Py_DECREF(solutions);
    return answer;
}

/* The Params and the Seed block of two bytes objects (exactly their sizes) into P and S: 1, else
   0 (no error set). */
static int read_blocks(PyObject *params, PyObject *seed_block, Params *P, Seed *S)
{
    if (!PyBytes_Check(params) || PyBytes_GET_SIZE(params) != sizeof *P ||
        !PyBytes_Check(seed_block) || PyBytes_GET_SIZE(seed_block) != sizeof *S)
        return 0;
    memcpy(P, PyBytes_AS_STRING(params), sizeof *P);
    memcpy(S, PyBytes_AS_STRING(seed_block), sizeof *S);
    return 1;
}

/* Whether the n values are all finite. */
static inline int all_finite(const double *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

static PyObject *seeded(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 15) {
        PyErr_SetString(PyExc_TypeError,
                        "seeded(params, seed_block, steps, solution, result, name, message, "
                        "method, clock, target, seed, position_tol, rotation_tol, start, out)");
        return NULL;
    }
    PyObject *steps = args[2], *solution = args[3], *result = args[4], *clock = args[8];
    Params P;
    Seed S;
    if (!read_blocks(args[0], args[1], &P, &S) || !PyTuple_Check(steps) ||
        !PyType_Check(solution) || !PyType_Check(result) || !PyCallable_Check(clock)) {
        PyErr_SetString(PyExc_ValueError, "params, seed_block: bytes of the blocks; steps: a "
                                          "tuple; solution, result: classes; clock: a callable");
        return NULL;
    }
    double position_tol = PyFloat_AsDouble(args[11]), rotation_tol = PyFloat_AsDouble(args[12]);
    double start = PyFloat_AsDouble(args[13]);
    if (PyErr_Occurred()) return NULL;
    double p[3], r[9] = {0.0}, seed[7], T[12], q[7];
    int mode = target_values(args[9], p, r);
    if (mode < 0 || (mode == 1 && !SEEDED_POINTS) || !copy_doubles(args[10], 7, seed))
        Py_RETURN_NONE;
    if (!all_finite(p, 3) || !all_finite(r, 9) || !all_finite(seed, 7)) Py_RETURN_NONE;
    double bx = p[0] - S.reach[0], by = p[1] - S.reach[1], bz = p[2] - S.reach[2];
    if (!(sqrt(bx * bx + by * by + bz * bz) <= S.reach[3])) Py_RETURN_NONE;
    prepare_seeded(&S, mode, p, r, T);
    for (Py_ssize_t k = 0; k < PyTuple_GET_SIZE(steps); k++) {
        double step = PyFloat_AsDouble(PyTuple_GET_ITEM(steps, k));
        if (step == -1.0 && PyErr_Occurred()) return NULL;
        if (first_start(&P, mode, T, seed, 1, step, q) != 0) continue;
        double pose[12], position_error, rotation_error;
        chain_pose7(&S, q, pose);
        pose_errors(pose, p, r, &position_error, &rotation_error);
        if (!(position_error < position_tol) || (mode == 0 && !(rotation_error < rotation_tol)))
            continue;
        return seeded_result(args, q, position_error, mode == 1 ? NAN : rotation_error, start);
    }
    Py_RETURN_FALSE;
}

/*
 * seeded_many(params, seed_block, limits, mode, tolerances, targets, starts, out, steps) -> int
 *   The batch's closed-form stage (kin/ik/batch_solve.py): for each of N world targets, the first
 *   scan step whose first() from its own start gives a branch, that branch measured by the
 *   table's DH product and kept when both errors are strictly below the tolerances and every
 *   joint is inside the limits. A target beyond the Seed block's reach bound (or not finite)
 *   gets no answer, without a scan. All of it without the GIL (threads share the work by rows).
 *   params, seed_block: bytes of the structure's Params and of its Seed block (as seeded's);
 *   limits:     float64[14], the arm's lower then upper joint limits [rad] (the judge's);
 *   mode:       0 = poses, targets float64[N, 12]: position [m] then R_world_tool row-major;
 *               1 = points, targets float64[N, 3] [m] (no answer where first() takes no point);
 *   tolerances: float64[2], position [m] and rotation [rad];
 *   starts:     float64[N, 7] [rad];
 *   out:        float64[N, 9] receives per row q (7) [rad], the position error [m] and the
 *               rotation error [rad] (NaN for a point), or nine NaN where no branch is kept;
 *   steps:      float64[m], the scan steps [rad] (0.0: the start's free joint only).
 *   Returns how many rows got an answer.
 */
static PyObject *seeded_many(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *params_obj, *seed_obj, *objs[6];
    static const char *const names[6] = {"limits", "tolerances", "targets", "starts", "out",
                                         "steps"};
    static const int writable[6] = {0, 0, 0, 0, 1, 0};
    int mode;
    if (!PyArg_ParseTuple(args, "SSOiOOOOO", &params_obj, &seed_obj, &objs[0], &mode, &objs[1],
                          &objs[2], &objs[3], &objs[4], &objs[5]))
        return NULL;
    if (PyBytes_GET_SIZE(params_obj) != sizeof(Params) || PyBytes_GET_SIZE(seed_obj) != sizeof(Seed)) {
        PyErr_SetString(PyExc_ValueError, "params, seed_block: bytes of the blocks");
        return NULL;
    }
    Py_buffer views[6];
    if (!get_buffers(6, objs, views, writable, names)) return NULL;
    Py_buffer *limits = &views[0], *tolerances = &views[1], *targets = &views[2],
              *starts = &views[3], *out = &views[4], *steps = &views[5];
    Py_ssize_t width = mode == 1 ? 3 : 12, n = 0, found = 0;
    const char *error = NULL;
    if (mode != 0 && mode != 1) error = "mode must be 0 (pose) or 1 (position)";
    else if (limits->len != 14 * (Py_ssize_t)sizeof(double)) error = "limits: not 14 float64";
    else if (tolerances->len != 2 * (Py_ssize_t)sizeof(double)) error = "tolerances: not 2 float64";
    else if (targets->ndim != 2 || targets->shape[1] != width) error = "targets: not N x width float64";
    else if (starts->ndim != 2 || starts->shape[1] != 7 || starts->shape[0] != targets->shape[0])
        error = "starts: not N x 7 float64";
    else if (out->ndim != 2 || out->shape[1] != 9 || out->shape[0] != targets->shape[0])
        error = "out: not N x 9 float64";
    else if (steps->ndim != 1) error = "steps: not a float64 vector";
    if (error == NULL) {
        Params P;
        Seed S;
        memcpy(&P, PyBytes_AS_STRING(params_obj), sizeof P);
        memcpy(&S, PyBytes_AS_STRING(seed_obj), sizeof S);
        const double *lo = limits->buf, *hi = lo + 7, *tol = tolerances->buf, *step = steps->buf;
        const double *all = targets->buf, *Q = starts->buf;
        double *rows = out->buf;
        Py_ssize_t n_steps = steps->shape[0];
        n = targets->shape[0];
        Py_BEGIN_ALLOW_THREADS
        for (Py_ssize_t i = 0; i < n; i++) {
            double *row = rows + 9 * i, p[3], r[9] = {0.0}, T[12], q[7];
            const double *t = all + width * i;
            for (int k = 0; k < 9; k++) row[k] = NAN;
            if (mode == 1 && !SEEDED_POINTS) continue;
            memcpy(p, t, sizeof p);
            if (mode == 0) memcpy(r, t + 3, sizeof r);
            double bx = p[0] - S.reach[0], by = p[1] - S.reach[1], bz = p[2] - S.reach[2];
            if (!(sqrt(bx * bx + by * by + bz * bz) <= S.reach[3])) continue; /* beyond reach */
            prepare_seeded(&S, mode, p, r, T);
            for (Py_ssize_t k = 0; k < n_steps; k++) {
                if (first_start(&P, mode, T, Q + 7 * i, 1, step[k], q) != 0) continue;
                double pose[12], position_error, rotation_error;
                chain_pose7(&S, q, pose);
                pose_errors(pose, p, r, &position_error, &rotation_error);
                int keep = position_error < tol[0] && (mode == 1 || rotation_error < tol[1]);
                for (int j = 0; j < 7; j++) keep = keep && lo[j] <= q[j] && q[j] <= hi[j];
                if (keep) {
                    memcpy(row, q, sizeof q);
                    row[7] = position_error;
                    row[8] = mode == 1 ? NAN : rotation_error;
                    found++;
                }
                break; /* the first step with a branch decides */
            }
        }
        Py_END_ALLOW_THREADS
    }
    release_buffers(6, views);
    if (error != NULL) {
        PyErr_SetString(PyExc_ValueError, error);
        return NULL;
    }
    return PyLong_FromSsize_t(found);
}

/* The docstring of seeded_many in the method tables. */
#define SEEDED_MANY_DOC                                                                        \
    "seeded_many(params, seed_block, limits, mode, tolerances, targets, starts, out, steps) -> " \
    "how many of the N world targets got a verified branch (q and its errors in out's rows). " \
    "See kin/_native/ik/analytic/seven_r/_seeded7.h."

/* The docstring of seeded in the method tables. */
#define SEEDED_DOC                                                                           \
    "seeded(params, seed_block, steps, solution, result, name, message, method, clock, "     \
    "target, seed, position_tol, rotation_tol, start, out) -> the IKResult of "              \
    "the answer from the seed, False (none within the tolerances), or None (a target or seed " \
    "the call does not take). See kin/_native/ik/analytic/seven_r/_seeded7.h."

#endif

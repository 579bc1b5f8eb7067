/*
 * The Python side of a 6R twin (solve, verify, the module set-up; see _six_r_twin.h), included
 * by _three_parallel.c and _pieper_arms.c after their Params and solve_one.
 */
#ifndef KIN_IK_ANALYTIC_SIX_R_MODULE_H
#define KIN_IK_ANALYTIC_SIX_R_MODULE_H

#include "_six_r_twin.h"

#include "_results.h"

/* p_0_6, R_0_6 of a world target, then its branches. */
static inline void solve_world(const Params *P, const double *pw, const double *rw, double free,
                               double out[BRANCHES][JOINTS])
{
    double p[3], r[9];
    to_frame6(P->base_r, P->base_t, P->tool_r, P->tool_t, P->plain, pw, rw, p, r);
    solve_one(P, p, r, free, out);
}

static PyObject *solve(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *objs[4];
    static const char *const names[4] = {"params", "positions", "rotations", "out"};
    static const int writable[4] = {0, 0, 0, 1};
    Py_buffer views[4];
    double free;
    if (!PyArg_ParseTuple(args, "OOOdO", &objs[0], &objs[1], &objs[2], &free, &objs[3]))
        return NULL;
    if (!get_buffers(4, objs, views, writable, names)) return NULL;
    const char *error = NULL;
    Py_ssize_t n = views[1].len / (Py_ssize_t)(3 * sizeof(double));
    if (views[0].len != PARAM_COUNT * (Py_ssize_t)sizeof(double))
        error = "params: wrong size";
    else if (views[1].len != n * 3 * (Py_ssize_t)sizeof(double) ||
             views[2].len != n * 9 * (Py_ssize_t)sizeof(double) ||
             views[3].len != n * BRANCHES * JOINTS * (Py_ssize_t)sizeof(double))
        error = "positions, rotations, out: not N x 3, N x 3 x 3, N x 8 x 6 float64";
    if (error == NULL) {
        const Params *P = views[0].buf;
        const double *pw = views[1].buf, *rw = views[2].buf;
        double(*out)[BRANCHES][JOINTS] = views[3].buf;
        Py_BEGIN_ALLOW_THREADS
        for (Py_ssize_t k = 0; k < n; k++) solve_world(P, pw + 3 * k, rw + 9 * k, free, out[k]);
        Py_END_ALLOW_THREADS
    }
    release_buffers(4, views);
    if (error != NULL) {
        PyErr_SetString(PyExc_ValueError, error);
        return NULL;
    }
    if (!quartic_ready()) return NULL;
    Py_RETURN_NONE;
}

static PyObject *verify(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *objs[7];
    static const char *const names[7] = {"params", "check", "position", "rotation",
                                         "seed",   "q",     "info"};
    static const int writable[7] = {0, 0, 0, 0, 0, 1, 1};
    Py_buffer views[7];
    double free;
    if (!PyArg_ParseTuple(args, "OOOOOdOO", &objs[0], &objs[1], &objs[2], &objs[3], &objs[4],
                          &free, &objs[5], &objs[6]))
        return NULL;
    if (!get_buffers(7, objs, views, writable, names)) return NULL;
    static const Py_ssize_t sizes[7] = {PARAM_COUNT, CHECK_COUNT, 3, 9, JOINTS,
                                        BRANCHES * JOINTS, BRANCHES * 4};
    const char *error = NULL;
    for (int i = 0; i < 7 && error == NULL; i++)
        if (views[i].len != sizes[i] * (Py_ssize_t)sizeof(double)) error = names[i];
    long found = 0;
    if (error == NULL) {
        const Params *P = views[0].buf;
        const Check *C = views[1].buf;
        const double *pw = views[2].buf, *rw = views[3].buf, *seed = views[4].buf;
        double(*q)[JOINTS] = views[5].buf, (*info)[4] = views[6].buf;
        for (int i = 0; i < 3; i++) found = isfinite(pw[i]) ? found : -1;
        for (int i = 0; i < 9; i++) found = isfinite(rw[i]) ? found : -1;
        if (found == 0) {
            solve_world(P, pw, rw, free, q);
            for (int b = 0; b < BRANCHES; b++) found += !isnan(q[b][0]);
            check_branches(C, pw, rw, seed, q, info);
        }
    }
    release_buffers(7, views);
    if (error != NULL) {
        PyErr_Format(PyExc_ValueError, "%s: wrong size", error);
        return NULL;
    }
    return PyLong_FromLong(found);
}

/* What solutions() makes its arrays with, set by six_r_module: numpy.ndarray, the float64
   dtype, the shapes (k, 6) for k = 0 .. BRANCHES, and the string "closed_form". */
static PyObject *np_ndarray, *np_float64, *row_shapes[BRANCHES + 1], *method_closed_form;

/* Whether two joint vectors are one branch: every joint within SAME_BRANCH [rad] modulo a turn
   (kin.ik.result.SAME_BRANCH; the 6R twins' joints are revolute). */
#define SAME_BRANCH 1e-6
static int same_branch(const double *a, const double *b)
{
    for (int i = 0; i < JOINTS; i++)
        if (fabs(remainder(a[i] - b[i], TWO_PI)) > SAME_BRANCH) return 0;
    return 1;
}

/*
 * solutions(params, check, directions, solution, labels, result, name, messages, clock, target,
 * seed, start): verify()'s work on the target's position and rotation (target_values in
 * _twin.h: a PoseTarget's packed values, or its arrays), then the answer as ClosedFormSolver returns it. When
 * a branch is valid and none is off target, the IKResult itself (class result: success, solver
 * name, status "ok", message messages[n - 1] for n valid, the two tuples below, no distance, 0
 * iterations, time clock() - start [s], method "closed_form", nothing free); else
 * (valid, rejected, off), valid the
 * IKSolution of each branch inside the limits and on target, nearest the seed first (a stable
 * order), rejected those on target outside the limits (branch order), off (label, position
 * error [m], rotation error [rad]) of those off target; the joint vectors are rows of one
 * read-only (k, 6) array. params, check: bytes of the two blocks; directions: bytes of 6 float64
 * (the arm's q = direction * q', seed and answers mapped) or None; solution: the IKSolution
 * class; labels: the 8 branch labels. Returns an int instead when there is no such answer: -1 a
 * target value that is not finite, 0 no branch, -2 a seed that is not 6 finite float64 (the
 * caller checks it and names what is wrong).
 */
static PyObject *solutions(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 12) {
        PyErr_SetString(PyExc_TypeError, "solutions(params, check, directions, solution, labels, "
                                         "result, name, messages, clock, target, seed, start)");
        return NULL;
    }
    PyObject *directions = args[2], *cls = args[3], *labels = args[4], *result = args[5],
             *name = args[6], *messages = args[7], *clock = args[8];
    double start = PyFloat_AsDouble(args[11]);
    if (start == -1.0 && PyErr_Occurred()) return NULL;
    if (!PyBytes_Check(args[0]) || PyBytes_GET_SIZE(args[0]) != sizeof(Params) ||
        !PyBytes_Check(args[1]) || PyBytes_GET_SIZE(args[1]) != sizeof(Check) ||
        (directions != Py_None &&
         (!PyBytes_Check(directions) || PyBytes_GET_SIZE(directions) != JOINTS * sizeof(double))) ||
        !PyType_Check(cls) || !PyTuple_Check(labels) || PyTuple_GET_SIZE(labels) != BRANCHES ||
        !PyType_Check(result) || !PyTuple_Check(messages) ||
        PyTuple_GET_SIZE(messages) != BRANCHES || !PyCallable_Check(clock)) {
        PyErr_SetString(PyExc_ValueError,
                        "params, check, directions: bytes of the blocks (directions None or 6 "
                        "float64); solution, result: classes; labels, messages: 8 strings; "
                        "clock: a callable");
        return NULL;
    }
    Params P;
    Check C;
    double dir[JOINTS], pw[3], rw[9], seed[JOINTS] = {0.0};
    memcpy(&P, PyBytes_AS_STRING(args[0]), sizeof P);
    memcpy(&C, PyBytes_AS_STRING(args[1]), sizeof C);
    for (int i = 0; i < JOINTS; i++) dir[i] = 1.0;
    if (directions != Py_None) memcpy(dir, PyBytes_AS_STRING(directions), sizeof dir);
    if (target_values(args[9], pw, rw) != 0) {
        PyErr_SetString(PyExc_TypeError, "target: position, rotation: C-contiguous float64 (3,), "
                                         "(3, 3)");
        return NULL;
    }
    if (args[10] != Py_None) {
        if (!copy_doubles(args[10], JOINTS, seed)) return PyLong_FromLong(-2);
        for (int i = 0; i < JOINTS; i++) {
            if (!isfinite(seed[i])) return PyLong_FromLong(-2);
            seed[i] *= dir[i]; /* the forward table's q' */
        }
    }
    for (int i = 0; i < 3; i++)
        if (!isfinite(pw[i])) return PyLong_FromLong(-1);
    for (int i = 0; i < 9; i++)
        if (!isfinite(rw[i])) return PyLong_FromLong(-1);
    double q[BRANCHES][JOINTS], info[BRANCHES][4];
    int valid[BRANCHES], rejected[BRANCHES], off[BRANCHES], n_valid = 0, n_rejected = 0,
                                                             n_off = 0, found = 0;
    solve_world(&P, pw, rw, 0.0, q);
    if (!quartic_ready()) return NULL;
    check_branches(&C, pw, rw, seed, q, info);
    for (int b = 0; b < BRANCHES; b++) {
        if (isnan(q[b][0])) continue;
        found++;
        if (info[b][0] == 1.0) { /* stable insertion by distance to the seed */
            int at = n_valid++;
            while (at > 0 && info[valid[at - 1]][3] > info[b][3]) {
                valid[at] = valid[at - 1];
                at--;
            }
            valid[at] = b;
        } else if (info[b][0] == 2.0) {
            rejected[n_rejected++] = b;
        } else {
            off[n_off++] = b;
        }
    }
    if (found == 0) return PyLong_FromLong(0);
    int kept = n_valid + n_rejected, order[BRANCHES];
    memcpy(order, valid, (size_t)n_valid * sizeof(int));
    memcpy(order + n_valid, rejected, (size_t)n_rejected * sizeof(int));
    /* Two kept branches that are one joint vector (a wrist flip with the wrist straight): the
       answer goes back as (valid, rejected, off), whose result kin.ik.result merges and says so
       (IKResult.without_repeats: every joint within SAME_BRANCH, modulo a turn). */
    int repeats = 0;
    for (int k = 1; k < kept && !repeats; k++)
        for (int j = 0; j < k && !repeats; j++) repeats = same_branch(q[order[k]], q[order[j]]);
    /* The rows, written into a bytes object: the array on it is read-only (its buffer is). */
    PyObject *data = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)(kept * JOINTS * sizeof(double)));
    if (data == NULL) return NULL;
    double(*out)[JOINTS] = (double(*)[JOINTS])PyBytes_AS_STRING(data);
    for (int k = 0; k < kept; k++)
        for (int i = 0; i < JOINTS; i++) out[k][i] = q[order[k]][i] * dir[i];
    PyObject *call[3] = {row_shapes[kept], np_float64, data};
    PyObject *rows = PyObject_Vectorcall(np_ndarray, call, 3, NULL);
    Py_DECREF(data);
    if (rows == NULL) return NULL;
    PyObject *answer = NULL, *valid_t = PyTuple_New(n_valid), *rejected_t = PyTuple_New(n_rejected),
             *off_t = PyTuple_New(n_off);
    if (valid_t == NULL || rejected_t == NULL || off_t == NULL) goto end;
    for (int k = 0; k < kept; k++) {
        int b = order[k];
        PyObject *solution =
            make_solution((PyTypeObject *)cls, PySequence_GetItem(rows, k),
                          PyTuple_GET_ITEM(labels, b), k < n_valid, info[b][1], info[b][2]);
        if (solution == NULL) goto end;
        if (k < n_valid)
            PyTuple_SET_ITEM(valid_t, k, solution);
        else
            PyTuple_SET_ITEM(rejected_t, k - n_valid, solution);
    }
    for (int k = 0; k < n_off; k++) {
        int b = off[k];
        PyObject *entry = Py_BuildValue("(Odd)", PyTuple_GET_ITEM(labels, b), info[b][1],
                                        info[b][2]);
        if (entry == NULL) goto end;
        PyTuple_SET_ITEM(off_t, k, entry);
    }
    if (n_valid > 0 && n_off == 0 && !repeats) {
        PyObject *now = PyObject_CallNoArgs(clock);
        double elapsed = now == NULL ? -1.0 : PyFloat_AsDouble(now) - start;
        Py_XDECREF(now);
        if (PyErr_Occurred()) goto end;
        PyObject *message = PyTuple_GET_ITEM(messages, n_valid - 1);
        answer = make_success((PyTypeObject *)result, name, status_ok, message, valid_t,
                              rejected_t, 0, elapsed, method_closed_form);
    } else {
        answer = PyTuple_Pack(3, valid_t, rejected_t, off_t);
    }
end:
    Py_DECREF(rows);
    Py_XDECREF(valid_t);
    Py_XDECREF(rejected_t);
    Py_XDECREF(off_t);
    return answer;
}

static PyMethodDef methods[] = {
    {"solutions", (PyCFunction)(void (*)(void))solutions, METH_FASTCALL,
     "solutions(params, check, directions, solution, labels, result, name, messages, clock, "
     "target, seed, start) -> the IKResult, or (valid, rejected, off), or -1 (a target value not finite), 0 (no branch), -2 (a seed that "
     "is not 6 finite float64). See kin/_native/ik/analytic/six_r/_six_r_module.h."},
    {"solve", solve, METH_VARARGS,
     "solve(params, positions, rotations, free, out): the 8 branches of N targets into out "
     "(N x 8 x 6). See kin/_native/ik/analytic/six_r/_six_r_twin.h."},
    {"verify", verify, METH_VARARGS,
     "verify(params, check, position, rotation, seed, free, q, info) -> branches found, or -1 "
     "for a target that is not finite. See kin/_native/ik/analytic/six_r/_six_r_twin.h."},
    {NULL, NULL, 0, NULL}};

/* The module: LAYOUT, PARAM_COUNT (the twin's), CHECK_LAYOUT, CHECK_COUNT. */
static inline PyObject *six_r_module(PyModuleDef *def)
{
    PyObject *numpy = PyImport_ImportModule("numpy");
    if (numpy == NULL) return NULL;
    np_ndarray = PyObject_GetAttrString(numpy, "ndarray");
    np_float64 = np_ndarray == NULL ? NULL : PyObject_GetAttrString(numpy, "float64");
    Py_DECREF(numpy);
    if (np_float64 == NULL) return NULL;
    for (int k = 0; k <= BRANCHES; k++)
        if ((row_shapes[k] = Py_BuildValue("(ii)", k, JOINTS)) == NULL) return NULL;
    if (results_init() < 0) return NULL;
    if ((method_closed_form = PyUnicode_InternFromString("closed_form")) == NULL) return NULL;
    PyObject *m = twin_module(def, FIELDS, sizeof FIELDS / sizeof FIELDS[0], PARAM_COUNT);
    if (m == NULL) return NULL;
    if (add_layout(m, "CHECK_LAYOUT", CHECK_FIELDS, sizeof CHECK_FIELDS / sizeof CHECK_FIELDS[0]) < 0)
        goto fail;
    if (PyModule_AddIntConstant(m, "CHECK_COUNT", CHECK_COUNT) < 0) goto fail;
    return m;
fail:
    Py_DECREF(m);
    return NULL;
}

#endif

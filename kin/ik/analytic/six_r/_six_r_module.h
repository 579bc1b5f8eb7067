/*
 * The Python side of a 6R twin (solve, verify, the module set-up; see _six_r_twin.h), included
 * by _ur_wrist.c and _spherical_wrist.c after their Params and solve_one.
 */
#ifndef KIN_IK_ANALYTIC_SIX_R_MODULE_H
#define KIN_IK_ANALYTIC_SIX_R_MODULE_H

#include "_six_r_twin.h"

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
            for (int b = 0; b < BRANCHES; b++) {
                if (isnan(q[b][0])) {
                    memset(info[b], 0, sizeof info[b]);
                    continue;
                }
                found++;
                check_branch(C, pw, rw, seed, q[b], info[b]);
            }
        }
    }
    release_buffers(7, views);
    if (error != NULL) {
        PyErr_Format(PyExc_ValueError, "%s: wrong size", error);
        return NULL;
    }
    return PyLong_FromLong(found);
}

static PyMethodDef methods[] = {
    {"solve", solve, METH_VARARGS,
     "solve(params, positions, rotations, free, out): the 8 branches of N targets into out "
     "(N x 8 x 6). See kin/ik/analytic/_six_r_twin.h."},
    {"verify", verify, METH_VARARGS,
     "verify(params, check, position, rotation, seed, free, q, info) -> branches found, or -1 "
     "for a target that is not finite. See kin/ik/analytic/_six_r_twin.h."},
    {NULL, NULL, 0, NULL}};

/* The module: LAYOUT, PARAM_COUNT (the twin's), CHECK_LAYOUT, CHECK_COUNT. */
static inline PyObject *six_r_module(PyModuleDef *def)
{
    PyObject *m = twin_module(def, FIELDS, sizeof FIELDS / sizeof FIELDS[0], PARAM_COUNT);
    if (m == NULL) return NULL;
    size_t n = sizeof CHECK_FIELDS / sizeof CHECK_FIELDS[0];
    PyObject *layout = PyTuple_New((Py_ssize_t)n);
    if (layout == NULL) goto fail;
    for (size_t i = 0; i < n; i++) {
        PyObject *entry = Py_BuildValue("(snn)", CHECK_FIELDS[i].name, CHECK_FIELDS[i].offset,
                                        CHECK_FIELDS[i].size);
        if (entry == NULL) {
            Py_DECREF(layout);
            goto fail;
        }
        PyTuple_SET_ITEM(layout, (Py_ssize_t)i, entry);
    }
    if (PyModule_AddObject(m, "CHECK_LAYOUT", layout) < 0) {
        Py_DECREF(layout);
        goto fail;
    }
    if (PyModule_AddIntConstant(m, "CHECK_COUNT", CHECK_COUNT) < 0) goto fail;
    return m;
fail:
    Py_DECREF(m);
    return NULL;
}

#endif

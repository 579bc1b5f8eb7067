/*
 * The real roots of E(t) = h0 + hc cos t + hs sin t + hc2 cos 2t + hs2 sin 2t, the quartic of the
 * 6R closed forms' general families: the steps of kin/ik/analytic/six_r/_trig_quartic.py
 * (candidates_batch, polish_batch) for one equation, in the same order, so that the twins
 * (_pieper_arms.c, _three_parallel.c) give the NumPy form's roots. The companion matrix's
 * eigenvalues by LAPACK's dgeev (NumPy's eigvals calls it too): NumPy's own (the OpenBLAS its
 * wheels bundle, its address found by Python's ctypes, six_r_twin.quartic_twin) or else SciPy's
 * cython_lapack capsule, set by the twin's load_lapack() before its first general arm. Angles
 * [rad].
 */
#ifndef KIN_NATIVE_TRIG_QUARTIC_H
#define KIN_NATIVE_TRIG_QUARTIC_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>

#define QUARTIC_IMAG_TOL 1e-6 /* _trig_quartic.IMAG_TOL */
#define QUARTIC_STEPS 3       /* _trig_quartic.NEWTON_STEPS */
#define QUARTIC_MAX_STEP 0.1  /* _trig_quartic.MAX_STEP */
#define QUARTIC_CONVERGED 1e-15
#define QUARTIC_EPS 2.220446049250313e-16 /* _trig_quartic.EPS = 2**-52 */

typedef void quartic_dgeev_t(char *, char *, int *, double *, int *, double *, double *, double *,
                             int *, double *, int *, double *, int *, int *);
typedef void quartic_dgeev64_t(char *, char *, long long *, double *, long long *, double *,
                               double *, double *, long long *, double *, long long *, double *,
                               long long *, long long *);
static quartic_dgeev_t *quartic_dgeev = NULL;     /* 32-bit integers (SciPy's, an LP64 LAPACK) */
static quartic_dgeev64_t *quartic_dgeev64 = NULL; /* 64-bit integers (NumPy's ILP64 OpenBLAS) */

/* dgeev from scipy.linalg.cython_lapack: 1, or 0 with a Python error set. Needs the GIL. */
static int quartic_load_scipy(void)
{
    PyObject *module = PyImport_ImportModule("scipy.linalg.cython_lapack");
    if (module == NULL) return 0;
    PyObject *capi = PyObject_GetAttrString(module, "__pyx_capi__");
    Py_DECREF(module);
    if (capi == NULL) return 0;
    PyObject *capsule = PyDict_GetItemString(capi, "dgeev"); /* borrowed */
    if (capsule != NULL)
        quartic_dgeev = (quartic_dgeev_t *)PyCapsule_GetPointer(capsule,
                                                                PyCapsule_GetName(capsule));
    else
        PyErr_SetString(PyExc_ImportError, "scipy.linalg.cython_lapack has no dgeev");
    Py_DECREF(capi);
    return quartic_dgeev != NULL;
}

/* Set when quartic_candidates ran before load_lapack() (no dgeev: no candidates); cleared by
   load_lapack(). */
static volatile int quartic_missed = 0;

/* 1, or 0 with a RuntimeError when a quartic was met before load_lapack() (its roots were not
   found: the answer is void); the flag is cleared, so a later call that meets no quartic (the UR
   case) answers. Call after the work, with the GIL. */
static int quartic_ready(void)
{
    if (!quartic_missed) return 1;
    quartic_missed = 0;
    PyErr_SetString(PyExc_RuntimeError, "LAPACK's dgeev is not loaded: call load_lapack() first");
    return 0;
}

/* load_lapack(address=0, ilp64=False): dgeev at address (NumPy's LAPACK, found by the caller
   with ctypes), else from SciPy. */
static PyObject *load_lapack(PyObject *self, PyObject *args)
{
    (void)self;
    unsigned long long address = 0;
    int ilp64 = 0;
    if (!PyArg_ParseTuple(args, "|Kp", &address, &ilp64)) return NULL;
    quartic_missed = 0;
    if (quartic_dgeev != NULL || quartic_dgeev64 != NULL) Py_RETURN_NONE;
    if (address != 0) {
        if (ilp64)
            quartic_dgeev64 = (quartic_dgeev64_t *)(uintptr_t)address;
        else
            quartic_dgeev = (quartic_dgeev_t *)(uintptr_t)address;
        Py_RETURN_NONE;
    }
    if (!quartic_load_scipy()) return NULL;
    Py_RETURN_NONE;
}

static PyMethodDef quartic_methods[] = {
    {"load_lapack", load_lapack, METH_VARARGS,
     "load_lapack(address=0, ilp64=False) -> None: LAPACK's dgeev for the general families' "
     "quartic, at address (64-bit integers when ilp64), else from SciPy (ImportError without "
     "it); call before solving a general-family arm. The first call decides."},
    {NULL, NULL, 0, NULL}};

/* The candidate roots t[4] of one equation (candidates_batch): NaN where not real. */
static void quartic_candidates(double e0, double ec, double es, double ec2, double es2,
                               double t[4])
{
    int best = 0, nan_seen = 0;
    double top = 0.0;
    for (int k = 0; k < 8; k++) { /* argmax: the first of equal values (NaN: none usable) */
        double a = k * M_PI / 4;
        double value = fabs(e0 + ec * cos(a) + es * sin(a) + ec2 * cos(2 * a) + es2 * sin(2 * a));
        nan_seen |= isnan(value);
        if (k == 0 || value > top) top = value, best = k;
    }
    double a = best * M_PI / 4;
    int usable = top > 0.0 && !nan_seen;
    double ct = -cos(a), st = -sin(a), c2t = cos(2 * a), s2t = sin(2 * a), tau = a + M_PI;
    double hc = ec * ct + es * st, hs = es * ct - ec * st;
    double hc2 = ec2 * c2t + es2 * s2t, hs2 = es2 * c2t - ec2 * s2t;
    double lead = usable ? e0 - hc + hc2 : 1.0;
    double row[4] = {-(2.0 * hs - 4.0 * hs2) / lead, -(2.0 * e0 - 6.0 * hc2) / lead,
                     -(2.0 * hs + 4.0 * hs2) / lead, -(e0 + hc + hc2) / lead};
    int finite = usable;
    for (int j = 0; j < 4; j++) finite = finite && isfinite(row[j]);
    for (int j = 0; j < 4; j++) t[j] = NAN;
    double m[16] = {0.0}; /* column-major */
    if (finite) {
        for (int j = 0; j < 4; j++) m[4 * j] = row[j];
        m[1] = m[6] = m[11] = 1.0;
    }
    char no = 'N';
    double wr[4], wi[4], work[64], dummy[1];
    long long info = 0;
    if (quartic_dgeev64 == NULL && quartic_dgeev == NULL) {
        quartic_missed = 1; /* the caller raises (quartic_ready) */
        return;
    }
    if (quartic_dgeev64 != NULL) {
        long long n = 4, one = 1, lwork = 64;
        quartic_dgeev64(&no, &no, &n, m, &n, wr, wi, dummy, &one, dummy, &one, work, &lwork,
                        &info);
    } else {
        int n = 4, one = 1, lwork = 64, info32 = 0;
        quartic_dgeev(&no, &no, &n, m, &n, wr, wi, dummy, &one, dummy, &one, work, &lwork,
                      &info32);
        info = info32;
    }
    if (info != 0 || !finite) return;
    for (int j = 0; j < 4; j++)
        if (fabs(wi[j]) <= QUARTIC_IMAG_TOL * (1.0 + wr[j] * wr[j])) t[j] = tau + 2.0 * atan(wr[j]);
}

/* A caller's E at t: out = (E, dE/dt, the bound on |E| of a root, extra values at t). */
typedef void quartic_residual_t(const void *ctx, double t, double out[5]);

/* Safeguarded Newton steps from the starts t[4] (polish_batch); at[k]: the residual's values at
   the polished t[k]; returns, per start, whether |E| is within its bound (NaN starts: 0). */
static void quartic_polish(quartic_residual_t *f, const void *ctx, double t[4],
                           double at[4][5], int ok[4])
{
    double damping[4] = {1.0, 1.0, 1.0, 1.0};
    for (int k = 0; k < 4; k++) f(ctx, t[k], at[k]);
    for (int it = 0; it < QUARTIC_STEPS; it++) {
        double step[4];
        int any = 0;
        for (int k = 0; k < 4; k++) {
            double s = at[k][1] != 0.0 ? at[k][0] / at[k][1] : 0.0;
            if (fabs(s) > QUARTIC_MAX_STEP) s = 0.0;
            step[k] = s;
            any |= fabs(s) > QUARTIC_CONVERGED;
        }
        if (!any) break;
        for (int k = 0; k < 4; k++) {
            double trial = t[k] - damping[k] * step[k], next[5];
            f(ctx, trial, next);
            if (fabs(next[0]) < fabs(at[k][0])) {
                t[k] = trial;
                for (int i = 0; i < 5; i++) at[k][i] = next[i];
                damping[k] = 1.0;
            } else {
                damping[k] *= 0.5;
            }
        }
    }
    for (int k = 0; k < 4; k++) ok[k] = fabs(at[k][0]) <= at[k][2];
}

/* order[4]: the indices of key[4] ascending (NaN keys last), stable (argsort of 4). */
static void quartic_order(const double key[4], int order[4])
{
    double k[4];
    for (int i = 0; i < 4; i++) k[i] = isnan(key[i]) ? INFINITY : key[i], order[i] = i;
    for (int i = 1; i < 4; i++)
        for (int j = i; j > 0 && k[order[j]] < k[order[j - 1]]; j--) {
            int swap = order[j];
            order[j] = order[j - 1];
            order[j - 1] = swap;
        }
}

#endif

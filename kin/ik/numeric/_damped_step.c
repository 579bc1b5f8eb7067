/*
 * Compiled twin of one damped Newton step's linear algebra (kin/ik/numeric/damped_newton.py):
 *
 *   damped_step(jacobian, error, lam, out) -> int
 *
 *   out = J^T (J J^T + lam I)^-1 e  for J of shape (m, n) with 1 <= m <= 6, e of shape (m,) and
 *   out of shape (n,), every array float64 and C-contiguous (out writable), lam >= 0 [m^2].
 *
 * The normal matrix J J^T + lam I is factored by Cholesky (L L^T) and solved by two triangular
 * substitutions: the arithmetic of LAPACK's dposv, in one call instead of the three NumPy calls
 * (product, solve, product) of the Python step, which cost about 6 us more per step. Returns 0
 * when out is written; 1 when the normal matrix is not positive definite (a NaN included) and -1
 * when the arrays are not of that form, out untouched: the caller takes its NumPy way then.
 * Jacobian rows in [m] or [rad] per joint unit, error in [m] and [rad], out in joint units.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

#define MAX_ROWS 6

/* Whether view holds float64 values (format "d"), C-contiguous. */
static int float64(const Py_buffer *view)
{
    return view->itemsize == (Py_ssize_t)sizeof(double) && view->format != NULL &&
           strcmp(view->format, "d") == 0;
}

/* out = J^T (J J^T + lam I)^-1 e; 0, or 1 when the Cholesky factorization fails. */
static int step(const double *J, Py_ssize_t m, Py_ssize_t n, const double *e, double lam,
                double *out)
{
    double L[MAX_ROWS][MAX_ROWS], y[MAX_ROWS];
    for (Py_ssize_t i = 0; i < m; i++) {
        const double *ri = J + i * n;
        for (Py_ssize_t j = 0; j <= i; j++) {
            const double *rj = J + j * n;
            double s = 0.0;
            for (Py_ssize_t c = 0; c < n; c++) s += ri[c] * rj[c];
            if (i == j) s += lam;
            for (Py_ssize_t k = 0; k < j; k++) s -= L[i][k] * L[j][k];
            if (i == j) {
                if (!(s > 0.0)) return 1; /* not positive definite, or NaN */
                L[i][i] = sqrt(s);
            } else {
                L[i][j] = s / L[j][j];
            }
        }
    }
    for (Py_ssize_t i = 0; i < m; i++) { /* L y = e */
        double s = e[i];
        for (Py_ssize_t k = 0; k < i; k++) s -= L[i][k] * y[k];
        y[i] = s / L[i][i];
    }
    for (Py_ssize_t i = m - 1; i >= 0; i--) { /* L^T x = y (x in y) */
        double s = y[i];
        for (Py_ssize_t k = i + 1; k < m; k++) s -= L[k][i] * y[k];
        y[i] = s / L[i][i];
    }
    for (Py_ssize_t c = 0; c < n; c++) {
        double s = 0.0;
        for (Py_ssize_t r = 0; r < m; r++) s += y[r] * J[r * n + c];
        out[c] = s;
    }
    return 0;
}

static PyObject *damped_step(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 4) {
        PyErr_SetString(PyExc_TypeError, "damped_step(jacobian, error, lam, out)");
        return NULL;
    }
    double lam = PyFloat_AsDouble(args[2]);
    if (lam == -1.0 && PyErr_Occurred()) return NULL;
    Py_buffer jv, ev, ov;
    long result = -1;
    if (PyObject_GetBuffer(args[0], &jv, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) {
        PyErr_Clear();
        return PyLong_FromLong(-1);
    }
    if (PyObject_GetBuffer(args[1], &ev, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) {
        PyErr_Clear();
        PyBuffer_Release(&jv);
        return PyLong_FromLong(-1);
    }
    if (PyObject_GetBuffer(args[3], &ov, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | PyBUF_WRITABLE) != 0) {
        PyErr_Clear();
        PyBuffer_Release(&ev);
        PyBuffer_Release(&jv);
        return PyLong_FromLong(-1);
    }
    if (float64(&jv) && float64(&ev) && float64(&ov) && jv.ndim == 2 && ev.ndim == 1 &&
        ov.ndim == 1) {
        Py_ssize_t m = jv.shape[0], n = jv.shape[1];
        if (m >= 1 && m <= MAX_ROWS && n >= 1 && ev.shape[0] == m && ov.shape[0] == n &&
            lam >= 0.0)
            result = step((const double *)jv.buf, m, n, (const double *)ev.buf, lam,
                          (double *)ov.buf);
    }
    PyBuffer_Release(&ov);
    PyBuffer_Release(&ev);
    PyBuffer_Release(&jv);
    return PyLong_FromLong(result);
}

static PyMethodDef methods[] = {
    {"damped_step", (PyCFunction)(void (*)(void))damped_step, METH_FASTCALL,
     "damped_step(jacobian, error, lam, out) -> 0 with out = J^T (J J^T + lam I)^-1 e; 1 when "
     "J J^T + lam I is not positive definite, -1 when the arrays do not fit (out untouched). "
     "See kin/ik/numeric/damped_newton.py."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_damped_step",
                                    "Compiled twin of a damped Newton step's linear algebra "
                                    "(optional speed-up).",
                                    -1, methods};

PyMODINIT_FUNC PyInit__damped_step(void) { return PyModule_Create(&module); }

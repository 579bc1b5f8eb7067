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

/* The n1 x n2 float64 values of obj (n2 = 1: a vector of n1) into out, row-major, whatever its
   strides; 0 (no error set) if it is not such an array. */
static int read_doubles(PyObject *obj, Py_ssize_t n1, Py_ssize_t n2, double *out)
{
    Py_buffer view;
    if (PyObject_GetBuffer(obj, &view, PyBUF_STRIDES | PyBUF_FORMAT) != 0) {
        PyErr_Clear();
        return 0;
    }
    int ndim = n2 == 1 ? 1 : 2;
    int fits = float64(&view) && view.ndim == ndim && view.shape[0] == n1 &&
               (ndim == 1 || view.shape[1] == n2);
    if (fits) {
        const char *base = view.buf;
        for (Py_ssize_t i = 0; i < n1; i++)
            for (Py_ssize_t j = 0; j < n2; j++)
                out[i * n2 + j] = *(const double *)(base + i * view.strides[0] +
                                                    (ndim == 2 ? j * view.strides[1] : 0));
    }
    PyBuffer_Release(&view);
    return fits;
}

/* The rotation vector (axis times angle [rad], angle in [0, pi]) of the rotation matrix R. */
static void rotation_vector(const double R[9], double out[3])
{
    double c = 0.5 * (R[0] + R[4] + R[8] - 1.0);
    double w[3] = {0.5 * (R[7] - R[5]), 0.5 * (R[2] - R[6]), 0.5 * (R[3] - R[1])};
    double s = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]); /* sin(angle) */
    double angle = atan2(s, c);
    if (c > -0.9) { /* angle below about 154 deg: w is sin(angle) times the axis */
        double factor = s > 1e-8 ? angle / s : 1.0 + s * s / 6.0;
        for (int i = 0; i < 3; i++) out[i] = factor * w[i];
        return;
    }
    /* Near a half turn: the axis from the symmetric part, (R + R^T)/2 = c I + (1 - c) a a^T,
       by its largest diagonal term; its sign from w. */
    double one_c = 1.0 - c, a[3];
    int k = 0;
    if (R[4] > R[k * 4]) k = 1;
    if (R[8] > R[k * 4]) k = 2;
    double akk = (R[k * 4] - c) / one_c;
    a[k] = sqrt(akk > 0.0 ? akk : 0.0);
    for (int j = 0; j < 3; j++)
        if (j != k) a[j] = 0.5 * (R[j * 3 + k] + R[k * 3 + j]) / (one_c * a[k]);
    double norm = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double sign = a[0] * w[0] + a[1] * w[1] + a[2] * w[2] < 0.0 ? -1.0 : 1.0;
    for (int i = 0; i < 3; i++) out[i] = sign * angle * a[i] / norm;
}

/* pose_error(position, translation, rotation, orientation, e) -> (|e_p|^2, |e_r|^2)
   e[0:3] = position - translation [m], e[3:6] = the rotation vector of rotation orientation^T
   [rad] (target and tool axes in the world frame): damped Newton's error. Any strides;
   None (e untouched) for arrays of another form. */
static PyObject *pose_error(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError,
                        "pose_error(position, translation, rotation, orientation, e)");
        return NULL;
    }
    double p[3], t[3], Rt[9], Ro[9], R[9], e[6];
    if (!(read_doubles(args[0], 3, 1, p) && read_doubles(args[1], 3, 1, t) &&
          read_doubles(args[2], 3, 3, Rt) && read_doubles(args[3], 3, 3, Ro)))
        Py_RETURN_NONE;
    Py_buffer ev;
    if (PyObject_GetBuffer(args[4], &ev, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | PyBUF_WRITABLE) != 0) {
        PyErr_Clear();
        Py_RETURN_NONE;
    }
    if (!(float64(&ev) && ev.ndim == 1 && ev.shape[0] == 6)) {
        PyBuffer_Release(&ev);
        Py_RETURN_NONE;
    }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            R[i * 3 + j] = Rt[i * 3] * Ro[j * 3] + Rt[i * 3 + 1] * Ro[j * 3 + 1] +
                           Rt[i * 3 + 2] * Ro[j * 3 + 2];
    for (int i = 0; i < 3; i++) e[i] = p[i] - t[i];
    rotation_vector(R, e + 3);
    memcpy(ev.buf, e, sizeof e);
    PyBuffer_Release(&ev);
    return Py_BuildValue("(dd)", e[0] * e[0] + e[1] * e[1] + e[2] * e[2],
                         e[3] * e[3] + e[4] * e[4] + e[5] * e[5]);
}

/* advance(dq, bound, q, lower, upper, stepped) -> 1 inside the limits, 0 outside, -1 not taken
   dq scaled in place so that its largest |value| is at most bound (when bound > 0), then
   stepped = q + dq; every array float64 (n,), C-contiguous (dq and stepped writable). -1 (nothing
   written) for arrays of another form. */
static PyObject *advance(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 6) {
        PyErr_SetString(PyExc_TypeError, "advance(dq, bound, q, lower, upper, stepped)");
        return NULL;
    }
    double bound = PyFloat_AsDouble(args[1]);
    if (bound == -1.0 && PyErr_Occurred()) return NULL;
    static const int writable[6] = {1, 0, 0, 0, 0, 1};
    Py_buffer views[6];
    int got = 0, fits = 1;
    for (int k = 0; k < 6 && fits; k++) {
        if (k == 1) continue;
        int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable[k] ? PyBUF_WRITABLE : 0);
        if (PyObject_GetBuffer(args[k], &views[k], flags) != 0) {
            PyErr_Clear();
            fits = 0;
            break;
        }
        got |= 1 << k;
        fits = float64(&views[k]) && views[k].ndim == 1 && views[k].shape[0] == views[0].shape[0];
    }
    long result = -1;
    if (fits) {
        Py_ssize_t n = views[0].shape[0];
        double *dq = views[0].buf, *out = views[5].buf;
        const double *q = views[2].buf, *lo = views[3].buf, *hi = views[4].buf;
        if (bound > 0.0) {
            double scale = 0.0;
            for (Py_ssize_t i = 0; i < n; i++)
                if (fabs(dq[i]) > scale) scale = fabs(dq[i]);
            if (scale > bound) {
                double factor = bound / scale;
                for (Py_ssize_t i = 0; i < n; i++) dq[i] *= factor;
            }
        }
        result = 1;
        for (Py_ssize_t i = 0; i < n; i++) {
            out[i] = q[i] + dq[i];
            if (!(lo[i] <= out[i] && out[i] <= hi[i])) result = 0;
        }
    }
    for (int k = 0; k < 6; k++)
        if (got & (1 << k)) PyBuffer_Release(&views[k]);
    return PyLong_FromLong(result);
}

static PyMethodDef methods[] = {
    {"advance", (PyCFunction)(void (*)(void))advance, METH_FASTCALL,
     "advance(dq, bound, q, lower, upper, stepped) -> 1 inside the limits, 0 outside, -1 not "
     "taken: dq bounded in place, stepped = q + dq (see kin/ik/numeric/damped_newton.py)."},
    {"pose_error", (PyCFunction)(void (*)(void))pose_error, METH_FASTCALL,
     "pose_error(position, translation, rotation, orientation, e) -> squared position and "
     "rotation errors, e filled (see kin/ik/numeric/damped_newton.py), or None."},
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

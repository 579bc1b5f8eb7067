/*
 * Compiled twin of the check kin/ik/targets/target.py makes of a pose target on its short way (optional:
 * without it the Python check runs, with the same verdict; tests/native/test_pose_check.py holds them
 * to it). One question: are a position (float64, shape (3,)) and a rotation (float64, shape (3, 3),
 * C order) all finite, with max |R^T R - I| <= tolerance and det R > 0? Anything else (a NaN, a matrix to snap
 * or refuse) is answered 0, and the Python check then says what is wrong. exact_pack asks it of
 * the values of two numpy arrays, packed into bytes (a PoseTarget keeps them, its arrays are
 * views made on first read).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

/* Whether obj is a C-contiguous float64 array of shape (n) (ndim 1) or (n, n) (ndim 2): 1 and a
   view to release, else 0 (no error). */
static int doubles(PyObject *obj, Py_buffer *view, int ndim, Py_ssize_t n)
{
    if (PyObject_GetBuffer(obj, view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) {
        PyErr_Clear();
        return 0;
    }
    if (view->ndim != ndim || view->shape[0] != n || (ndim == 2 && view->shape[1] != n) ||
        view->itemsize != sizeof(double) || view->format == NULL || strcmp(view->format, "d") != 0) {
        PyBuffer_Release(view);
        return 0;
    }
    return 1;
}

/* max |R^T R - I| <= tol and det R > 0, every value finite (a NaN fails every comparison). */
static int exact(const double *p, const double *r, double tol)
{
    for (int k = 0; k < 3; k++)
        if (!isfinite(p[k])) return 0;
    for (int k = 0; k < 9; k++)
        if (!isfinite(r[k])) return 0;
    for (int i = 0; i < 3; i++)
        for (int j = i; j < 3; j++) {
            double dot = r[i] * r[j] + r[3 + i] * r[3 + j] + r[6 + i] * r[6 + j];
            if (!(fabs(dot - (i == j ? 1.0 : 0.0)) <= tol)) return 0;
        }
    double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                 r[2] * (r[3] * r[7] - r[4] * r[6]);
    return det > 0.0;
}

static PyObject *exact_pose(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "exact_pose(position, rotation, tolerance)");
        return NULL;
    }
    double tol = PyFloat_AsDouble(args[2]);
    if (tol == -1.0 && PyErr_Occurred()) return NULL;
    Py_buffer pv, rv;
    if (!doubles(args[0], &pv, 1, 3)) Py_RETURN_FALSE;
    if (!doubles(args[1], &rv, 2, 3)) {
        PyBuffer_Release(&pv);
        Py_RETURN_FALSE;
    }
    int ok = exact((const double *)pv.buf, (const double *)rv.buf, tol);
    PyBuffer_Release(&pv);
    PyBuffer_Release(&rv);
    return PyBool_FromLong(ok);
}

/* numpy.ndarray, set when the module is imported. */
static PyObject *ndarray_type;

/* The n x n (ndim 2) or n (ndim 1) float64 values of obj, any strides, into out (C order): 1,
   else 0 (no error: not such an array). */
static int gather(PyObject *obj, int ndim, Py_ssize_t n, double *out)
{
    Py_buffer view;
    if (PyObject_GetBuffer(obj, &view, PyBUF_STRIDES | PyBUF_FORMAT) != 0) {
        PyErr_Clear();
        return 0;
    }
    int ok = view.ndim == ndim && view.shape[0] == n && (ndim == 1 || view.shape[1] == n) &&
             view.itemsize == sizeof(double) && view.format != NULL &&
             strcmp(view.format, "d") == 0;
    if (ok) {
        const char *base = (const char *)view.buf;
        Py_ssize_t rows = ndim == 2 ? n : 1, row_stride = ndim == 2 ? view.strides[0] : 0;
        Py_ssize_t col_stride = view.strides[ndim - 1];
        for (Py_ssize_t i = 0; i < rows; i++)
            for (Py_ssize_t j = 0; j < n; j++)
                memcpy(out + i * n + j, base + i * row_stride + j * col_stride, sizeof(double));
    }
    PyBuffer_Release(&view);
    return ok;
}

/* exact_pack(position, rotation, tolerance) -> bytes of the 12 float64 values (position [m],
   then the rotation row-major) when both are numpy float64 arrays of shape (3,) and (3, 3) (any
   strides) whose values pass exact(); else None (the Python check says why). The bytes are
   immutable: what is kept is what was checked. */
static PyObject *exact_pack(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "exact_pack(position, rotation, tolerance)");
        return NULL;
    }
    if ((PyObject *)Py_TYPE(args[0]) != ndarray_type || (PyObject *)Py_TYPE(args[1]) != ndarray_type)
        Py_RETURN_NONE;
    double tol = PyFloat_AsDouble(args[2]);
    if (tol == -1.0 && PyErr_Occurred()) return NULL;
    double values[12];
    if (!gather(args[0], 1, 3, values) || !gather(args[1], 2, 3, values + 3) ||
        !exact(values, values + 3, tol))
        Py_RETURN_NONE;
    return PyBytes_FromStringAndSize((const char *)values, sizeof values);
}

static PyMethodDef methods[] = {
    {"exact_pack", (PyCFunction)(void (*)(void))exact_pack, METH_FASTCALL,
     "exact_pack(position, rotation, tolerance) -> bytes of the 12 float64 values of two numpy "
     "arrays that pass exact_pose, else None. See kin/ik/targets/target.py."},
    {"exact_pose", (PyCFunction)(void (*)(void))exact_pose, METH_FASTCALL,
     "exact_pose(position, rotation, tolerance) -> whether 3 + 9 float64 values are finite, with "
     "max |R^T R - I| <= tolerance and det R > 0. See kin/ik/targets/target.py."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_pose_check",
                                    "Compiled twin of kin.ik.targets.target's pose check (optional speed-up).",
                                    -1, methods};

PyMODINIT_FUNC PyInit__pose_check(void)
{
    PyObject *numpy = PyImport_ImportModule("numpy");
    if (numpy == NULL) return NULL;
    ndarray_type = PyObject_GetAttrString(numpy, "ndarray");
    Py_DECREF(numpy);
    if (ndarray_type == NULL) return NULL;
    return PyModule_Create(&module);
}

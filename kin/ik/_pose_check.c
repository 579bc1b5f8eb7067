/*
 * Compiled twin of the check kin/ik/target.py makes of a pose target on its short way (optional:
 * without it the Python check runs, with the same verdict; tests/test_pose_check.py holds them
 * to it). One question: are a position (float64, shape (3,)) and a rotation (float64, shape (3, 3),
 * C order) all finite, with max |R^T R - I| <= tolerance and det R > 0? Anything else (a NaN, a matrix to snap
 * or refuse) is answered 0, and the Python check then says what is wrong. exact_copies asks it of
 * read-only copies of two numpy arrays, made here (about 0.6 us less than in Python).
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

/* numpy.ndarray and the interned method names, set when the module is imported. */
static PyObject *ndarray_type, *copy_name, *setflags_name;

/* A read-only copy of array obj (obj.copy(), then setflags(False)), or NULL and an error. */
static PyObject *read_only_copy(PyObject *obj)
{
    PyObject *args[2] = {obj, NULL};
    PyObject *copy = PyObject_VectorcallMethod(copy_name, args, 1 | PY_VECTORCALL_ARGUMENTS_OFFSET, NULL);
    if (copy == NULL) return NULL;
    args[0] = copy;
    args[1] = Py_False;
    PyObject *done = PyObject_VectorcallMethod(setflags_name, args, 2 | PY_VECTORCALL_ARGUMENTS_OFFSET, NULL);
    if (done == NULL) {
        Py_DECREF(copy);
        return NULL;
    }
    Py_DECREF(done);
    return copy;
}

/* exact_copies(position, rotation, tolerance) -> (position copy, rotation copy), read-only, when
   both are numpy arrays whose copies pass exact(); else None (the Python check says why). */
static PyObject *exact_copies(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "exact_copies(position, rotation, tolerance)");
        return NULL;
    }
    if ((PyObject *)Py_TYPE(args[0]) != ndarray_type || (PyObject *)Py_TYPE(args[1]) != ndarray_type)
        Py_RETURN_NONE;
    double tol = PyFloat_AsDouble(args[2]);
    if (tol == -1.0 && PyErr_Occurred()) return NULL;
    /* Checked after the copy (C order; dtypes and shapes checked there): what is kept is checked. */
    PyObject *p = read_only_copy(args[0]);
    if (p == NULL) return NULL;
    PyObject *r = read_only_copy(args[1]);
    if (r == NULL) {
        Py_DECREF(p);
        return NULL;
    }
    Py_buffer pv, rv;
    int ok = 0;
    if (doubles(p, &pv, 1, 3)) {
        if (doubles(r, &rv, 2, 3)) {
            ok = exact((const double *)pv.buf, (const double *)rv.buf, tol);
            PyBuffer_Release(&rv);
        }
        PyBuffer_Release(&pv);
    }
    if (!ok) {
        Py_DECREF(p);
        Py_DECREF(r);
        Py_RETURN_NONE;
    }
    PyObject *pair = PyTuple_New(2);
    if (pair == NULL) {
        Py_DECREF(p);
        Py_DECREF(r);
        return NULL;
    }
    PyTuple_SET_ITEM(pair, 0, p);
    PyTuple_SET_ITEM(pair, 1, r);
    return pair;
}

static PyMethodDef methods[] = {
    {"exact_copies", (PyCFunction)(void (*)(void))exact_copies, METH_FASTCALL,
     "exact_copies(position, rotation, tolerance) -> read-only copies (position, rotation) of two "
     "numpy arrays that pass exact_pose, else None. See kin/ik/target.py."},
    {"exact_pose", (PyCFunction)(void (*)(void))exact_pose, METH_FASTCALL,
     "exact_pose(position, rotation, tolerance) -> whether 3 + 9 float64 values are finite, with "
     "max |R^T R - I| <= tolerance and det R > 0. See kin/ik/target.py."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_pose_check",
                                    "Compiled twin of kin.ik.target's pose check (optional speed-up).",
                                    -1, methods};

PyMODINIT_FUNC PyInit__pose_check(void)
{
    PyObject *numpy = PyImport_ImportModule("numpy");
    if (numpy == NULL) return NULL;
    ndarray_type = PyObject_GetAttrString(numpy, "ndarray");
    Py_DECREF(numpy);
    if (ndarray_type == NULL) return NULL;
    copy_name = PyUnicode_InternFromString("copy");
    setflags_name = PyUnicode_InternFromString("setflags");
    if (copy_name == NULL || setflags_name == NULL) return NULL;
    return PyModule_Create(&module);
}

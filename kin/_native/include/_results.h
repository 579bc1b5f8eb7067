/*
 * The IK results made in C (kin/ik/result.py's IKSolution and IKResult, as their __init__ makes
 * them) by the compiled twins that answer a whole call: the 6R closed forms' solutions()
 * (_six_r_module.h) and the 7R free-joint forms' seeded() (_seeded7.h). A module
 * calls results_init() when it is imported.
 */
#ifndef KIN_IK_ANALYTIC_RESULTS_H
#define KIN_IK_ANALYTIC_RESULTS_H

#include "_twin.h"

#include <structmember.h> /* READONLY, T_OBJECT_EX before Python 3.12 */

/* The field names of IKSolution and IKResult (in the order of their constructors), an empty
   tuple (object.__new__'s arguments and IKResult.free), the status "ok" and the empty branch
   label, set by results_init. */
#define SOLUTION_FIELDS 6
#define RESULT_FIELDS 11
static PyObject *solution_fields[SOLUTION_FIELDS], *result_fields[RESULT_FIELDS], *no_args, *status_ok,
    *empty_label;

/* The names above, made once when the module is imported: 0, else -1 and an error. */
static int results_init(void)
{
    static const char *const fields[SOLUTION_FIELDS] = {
        "q", "branch", "within_limits", "position_error", "rotation_error", "reason"};
    for (int i = 0; i < SOLUTION_FIELDS; i++)
        if ((solution_fields[i] = PyUnicode_InternFromString(fields[i])) == NULL) return -1;
    static const char *const results[RESULT_FIELDS] = {
        "success", "solver",     "status", "message", "solutions", "rejected",
        "distance_to_workspace", "iterations", "time", "method", "free"};
    for (int i = 0; i < RESULT_FIELDS; i++)
        if ((result_fields[i] = PyUnicode_InternFromString(results[i])) == NULL) return -1;
    if ((status_ok = PyUnicode_InternFromString("ok")) == NULL) return -1;
    if ((empty_label = PyUnicode_InternFromString("")) == NULL) return -1;
    return (no_args = PyTuple_New(0)) == NULL ? -1 : 0;
}

/* A new instance of cls (object.__new__, no __init__) when none of the n values is NULL, else
   NULL; on failure the values are released (their errors set). */
static PyObject *new_instance(PyTypeObject *cls, PyObject **values, int n)
{
    PyObject *obj = NULL;
    int complete = 1;
    for (int i = 0; i < n; i++) complete = complete && values[i] != NULL;
    if (complete) obj = PyBaseObject_Type.tp_new(cls, no_args, NULL);
    if (obj == NULL)
        for (int i = 0; i < n; i++) Py_XDECREF(values[i]);
    return obj;
}

/* An instance of cls (a frozen dataclass of kin.ik.result) with its n fields names[i] set to
   values[i], as its __init__ sets them (by the generic setattr, past the frozen __setattr__);
   the values are stolen (NULL ones make it fail: NULL, with their error set). */
static PyObject *make_instance(PyTypeObject *cls, PyObject *const *names, PyObject **values,
                               int n)
{
    PyObject *obj = new_instance(cls, values, n);
    if (obj == NULL) return NULL;
    for (int i = 0; i < n && obj != NULL; i++)
        if (PyObject_GenericSetAttr(obj, names[i], values[i]) < 0) Py_CLEAR(obj);
    for (int i = 0; i < n; i++) Py_DECREF(values[i]);
    return obj;
}

#ifndef Py_T_OBJECT_EX /* before Python 3.12 */
#define Py_T_OBJECT_EX T_OBJECT_EX
#endif

/* The slots of a class: the class whose offsets are held (a new reference), or NULL. */
typedef struct {
    PyTypeObject *cls;
    Py_ssize_t offsets[RESULT_FIELDS];
} Slots;

static Slots solution_slots_of, result_slots_of;

/* Whether cls stores the n fields names[i] in slots of its own (a dataclass with slots=True):
   then slots->offsets holds their offsets in the instance (kept for the next call with cls).
   Else 0 (no error): the fields are set by name. */
static int has_slots(PyTypeObject *cls, PyObject *const *names, int n, Slots *slots)
{
    if (cls == slots->cls) return 1;
    for (int i = 0; i < n; i++) {
        PyObject *descr = PyDict_GetItemWithError(cls->tp_dict, names[i]);
        if (descr == NULL || !Py_IS_TYPE(descr, &PyMemberDescr_Type)) {
            PyErr_Clear();
            return 0;
        }
        PyMemberDef *member = ((PyMemberDescrObject *)descr)->d_member;
        if (member->type != Py_T_OBJECT_EX || (member->flags & READONLY)) return 0;
        slots->offsets[i] = member->offset;
    }
    Py_INCREF(cls);
    Py_XSETREF(slots->cls, cls);
    return 1;
}

/* An instance of cls with its n fields names[i] set to values[i] (stolen; NULL ones make it
   fail: NULL, with their error set): straight into its slots when it has them (has_slots),
   else by name (make_instance). */
static PyObject *make_fields(PyTypeObject *cls, PyObject *const *names, PyObject **values, int n,
                             Slots *slots)
{
    if (!has_slots(cls, names, n, slots)) return make_instance(cls, names, values, n);
    PyObject *obj = new_instance(cls, values, n);
    if (obj == NULL) return NULL;
    for (int i = 0; i < n; i++) *(PyObject **)((char *)obj + slots->offsets[i]) = values[i];
    return obj;
}

/* An IKSolution (cls) of its fields, reason empty; q is stolen; rotation_error NaN stands for
   None (a position target). Written straight into its slots when it has them, else set by name as its __init__
   would (make_fields). */
static PyObject *make_solution(PyTypeObject *cls, PyObject *q, PyObject *label, int inside,
                               double position_error, double rotation_error)
{
    Py_INCREF(label);
    PyObject *rotation = Py_None;
    if (isnan(rotation_error))
        Py_INCREF(rotation);
    else
        rotation = PyFloat_FromDouble(rotation_error);
    Py_INCREF(empty_label); /* reason: none (a rejection's reason is set in Python) */
    PyObject *values[SOLUTION_FIELDS] = {
        q, label, PyBool_FromLong(inside), PyFloat_FromDouble(position_error), rotation,
        empty_label};
    return make_fields(cls, solution_fields, values, SOLUTION_FIELDS, &solution_slots_of);
}

/* A successful IKResult (cls) of one pipeline (name), status "ok", with its message, valid
   solutions and rejected ones (tuples), iterations, time [s] and method; nothing free. The
   arguments are borrowed; NULL and an error on failure. */
static PyObject *make_success(PyTypeObject *cls, PyObject *name, PyObject *status,
                              PyObject *message, PyObject *solutions, PyObject *rejected,
                              long iterations, double time, PyObject *method)
{
    PyObject *values[RESULT_FIELDS] = {Py_True, name,    status, message, solutions, rejected,
                                       Py_None, NULL,    NULL,   method,  no_args};
    for (int i = 0; i < RESULT_FIELDS; i++) Py_XINCREF(values[i]);
    values[7] = PyLong_FromLong(iterations);
    values[8] = PyFloat_FromDouble(time);
    return make_fields(cls, result_fields, values, RESULT_FIELDS, &result_slots_of);
}

#endif

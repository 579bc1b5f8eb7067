/*
 * Compiled twin of the plainest input lines' reading in kin/commands/ik_stream.py (the decoding
 * that _decoded does with the json module, for the one form json.dumps writes):
 *
 *   read(lines) -> (kinds, values)
 *
 *   lines:  a list of bytes objects, one input line each (without its newline);
 *   kinds:  bytes, one per line: 1 for {"target": [x, y, z]}, 2 for
 *           {"target": [x, y, z], "rpy": [r, p, y]}, exactly so spelled and spaced (the
 *           separators ", " and ": " of json.dumps), each number a JSON number; 0 for any other
 *           line, which the caller reads with the json module;
 *   values: bytes of 6 float64 per line (native byte order): x, y, z, r, p, y as the json module
 *           reads them (a JSON integer as Python's int converted to float, a JSON fraction as
 *           Python's float: both rounded correctly, -0 an integer zero), NaN where a line has
 *           no such value. A number too large for a float64 is infinite (the caller's finiteness
 *           check sends it to the line-by-line path, which says what is wrong).
 *
 * The values are in the units the user gave (the caller scales them); no value is checked here
 * beyond the JSON grammar.
 *
 * And the answers' writing, the twin of the %-format of _plain_group:
 *
 *   write(pieces, values, numbers) -> list of str, one answer line each
 *
 *   pieces:  a tuple of k + 2 ASCII strings: a line is pieces[0], value 0, pieces[1], ...,
 *            value k - 1, pieces[k], its number, pieces[k + 1];
 *   values:  a C-contiguous buffer of N * k float64, k per line, each written as the shortest
 *            text that reads back as the same float64 (_float_text.h; repr's layout);
 *   numbers: a C-contiguous buffer of N int64, the line numbers.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

#include "_float_text.h"

/* The longest number read here, in characters (json.dumps writes at most 24 for a float). */
#define LONGEST 40

static int is_digit(char c) { return c >= '0' && c <= '9'; }

/* The JSON number at *at (before end) into *out, *at moved past it: 1; 0 if there is none. */
static int number(const char **at, const char *end, double *out)
{
    const char *start = *at, *p = start;
    int integer = 1;
    if (p < end && *p == '-') p++;
    if (p >= end) return 0;
    if (*p == '0') {
        p++;
    } else if (*p >= '1' && *p <= '9') {
        while (p < end && is_digit(*p)) p++;
    } else {
        return 0;
    }
    if (p < end && *p == '.') {
        integer = 0;
        p++;
        if (p >= end || !is_digit(*p)) return 0;
        while (p < end && is_digit(*p)) p++;
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        integer = 0;
        p++;
        if (p < end && (*p == '+' || *p == '-')) p++;
        if (p >= end || !is_digit(*p)) return 0;
        while (p < end && is_digit(*p)) p++;
    }
    Py_ssize_t size = p - start;
    if (size > LONGEST) return 0; /* the json module reads it */
    char text[LONGEST + 1];
    memcpy(text, start, (size_t)size);
    text[size] = '\0';
    /* Python's own correctly rounded reading (float()); an overflow gives an infinity. */
    double value = PyOS_string_to_double(text, NULL, NULL);
    if (value == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        return 0;
    }
    if (integer && value == 0.0) value = 0.0; /* int("-0") is 0: no sign */
    *out = value;
    *at = p;
    return 1;
}

/* Whether the text at *at starts with the literal; *at moved past it. */
static int literal(const char **at, const char *end, const char *text)
{
    size_t size = strlen(text);
    if ((size_t)(end - *at) < size || memcmp(*at, text, size) != 0) return 0;
    *at += size;
    return 1;
}

/* [a, b, c] at *at into out[0..3). */
static int triple(const char **at, const char *end, double *out)
{
    return literal(at, end, "[") && number(at, end, out) && literal(at, end, ", ") &&
           number(at, end, out + 1) && literal(at, end, ", ") && number(at, end, out + 2) &&
           literal(at, end, "]");
}

/* The kind of one line (1, 2), its values read into values; 0 if it is of neither form. */
static char parse(const char *p, const char *end, double *values)
{
    if (!(literal(&p, end, "{\"target\": ") && triple(&p, end, values))) return 0;
    if (literal(&p, end, "}")) return p == end ? 1 : 0;
    if (literal(&p, end, ", \"rpy\": ") && triple(&p, end, values + 3) &&
        literal(&p, end, "}") && p == end)
        return 2;
    return 0;
}

/* parse(), the values all NaN for a line of kind 0 and the rpy NaN for kind 1. */
static char line_kind(const char *p, const char *end, double *values)
{
    for (int i = 0; i < 6; i++) values[i] = NAN;
    char kind = parse(p, end, values);
    if (kind == 0) /* a line read part of the way */
        for (int i = 0; i < 6; i++) values[i] = NAN;
    return kind;
}

static PyObject *read_lines(PyObject *self, PyObject *lines)
{
    (void)self;
    PyObject *seq = PySequence_Fast(lines, "read(lines): lines must be a sequence of bytes");
    if (seq == NULL) return NULL;
    Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
    PyObject **items = PySequence_Fast_ITEMS(seq);
    PyObject *kinds = PyBytes_FromStringAndSize(NULL, n);
    PyObject *values = PyBytes_FromStringAndSize(NULL, n * 6 * (Py_ssize_t)sizeof(double));
    if (kinds == NULL || values == NULL) {
        Py_XDECREF(kinds);
        Py_XDECREF(values);
        Py_DECREF(seq);
        return NULL;
    }
    char *kind = PyBytes_AS_STRING(kinds);
    double *value = (double *)PyBytes_AS_STRING(values);
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *item = items[i];
        double *row = value + 6 * i;
        if (PyBytes_Check(item)) {
            const char *p = PyBytes_AS_STRING(item);
            kind[i] = line_kind(p, p + PyBytes_GET_SIZE(item), row);
        } else {
            kind[i] = 0;
            for (int k = 0; k < 6; k++) row[k] = NAN;
        }
    }
    Py_DECREF(seq);
    return Py_BuildValue("(NN)", kinds, values);
}

/* The text of a long long at out (no terminating zero); returns its end. */
static char *integer_text(long long value, char *out)
{
    char reversed[24];
    int n = 0;
    unsigned long long magnitude = value < 0 ? 0ull - (unsigned long long)value
                                             : (unsigned long long)value;
    do {
        reversed[n++] = (char)('0' + magnitude % 10);
        magnitude /= 10;
    } while (magnitude);
    if (value < 0) *out++ = '-';
    while (n) *out++ = reversed[--n];
    return out;
}

static PyObject *write_lines(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *pieces, *out = NULL;
    Py_buffer values, numbers;
    if (!PyArg_ParseTuple(args, "O!y*y*", &PyTuple_Type, &pieces, &values, &numbers)) return NULL;
    Py_ssize_t parts = PyTuple_GET_SIZE(pieces), k = parts - 2, fixed = 0;
    Py_ssize_t n = numbers.len / (Py_ssize_t)sizeof(long long);
    const char *error = NULL;
    if (k < 0)
        error = "pieces: at least 2 strings";
    else if (numbers.len != n * (Py_ssize_t)sizeof(long long) ||
             values.len != n * k * (Py_ssize_t)sizeof(double))
        error = "values, numbers: N * k float64 and N int64 (k = len(pieces) - 2)";
    for (Py_ssize_t i = 0; i < parts && error == NULL; i++) {
        PyObject *piece = PyTuple_GET_ITEM(pieces, i);
        if (!PyUnicode_Check(piece) || !PyUnicode_IS_ASCII(piece))
            error = "pieces: ASCII strings";
        else
            fixed += PyUnicode_GET_LENGTH(piece);
    }
    char *line = NULL;
    if (error == NULL) {
        line = PyMem_Malloc((size_t)(fixed + k * FLOAT_TEXT_MAX + 24));
        out = line == NULL ? PyErr_NoMemory() : PyList_New(n);
    }
    const double *value = values.buf;
    const long long *number = numbers.buf;
    for (Py_ssize_t row = 0; out != NULL && row < n; row++) {
        char *at = line;
        for (Py_ssize_t i = 0; i < parts; i++) {
            PyObject *piece = PyTuple_GET_ITEM(pieces, i);
            Py_ssize_t size = PyUnicode_GET_LENGTH(piece);
            memcpy(at, PyUnicode_DATA(piece), (size_t)size);
            at += size;
            if (i < k)
                at = float_text(value[row * k + i], at);
            else if (i == k)
                at = integer_text(number[row], at);
        }
        PyObject *text = PyUnicode_New(at - line, 127);
        if (text == NULL) {
            Py_CLEAR(out);
            break;
        }
        memcpy(PyUnicode_DATA(text), line, (size_t)(at - line));
        PyList_SET_ITEM(out, row, text);
    }
    PyMem_Free(line);
    PyBuffer_Release(&values);
    PyBuffer_Release(&numbers);
    if (error != NULL) PyErr_SetString(PyExc_ValueError, error);
    return out;
}

static PyMethodDef methods[] = {
    {"read", read_lines, METH_O,
     "read(lines) -> (kinds, values): the plainest stream lines read into float64 values (6 per "
     "line); kind 0 for a line to read with the json module. See kin/commands/ik_stream.py."},
    {"write", write_lines, METH_VARARGS,
     "write(pieces, values, numbers) -> list of str: the answer lines of the plainest lines, "
     "each float64 as its shortest text. See kin/commands/ik_stream.py."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_plain_lines",
                                    "Compiled twin of kin ik --stdin's reading of its plainest "
                                    "lines and writing of their answers (optional speed-up).",
                                    -1, methods};

PyMODINIT_FUNC PyInit__plain_lines(void) { return PyModule_Create(&module); }

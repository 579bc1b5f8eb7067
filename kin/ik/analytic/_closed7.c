/*
 * Compiled twin of ik/seven_dof.py (SevenDofIK.pose / SevenDofIK.position and the choice of the
 * branch nearest a start): the same arithmetic, operation for operation, for speed. The Python
 * module is the reference and the fallback when this extension is not built; the tests compare the
 * two. Angles in radians, lengths in meters.
 *
 * first(params, mode, target, starts, out, step) -> int
 *   params: float64[PARAM_COUNT], SevenDofIK.c_params (layout below);
 *   mode:   0 = full pose, target = float64[12]: tool origin of DH frame 7 in frame 0 (3), then
 *           R_0_7 row-major (9); 1 = position, target = float64[3]: the tool point in frame 0;
 *   starts: float64[k, 7], start joint vectors (clipped into the limits here; a row with a value
 *           that is not finite is skipped). Joint 1 (and, for a position, joints 5-7) are taken
 *           from the start, the others solved;
 *   out:    float64[7], receives the solution.
 *   step:   when > 0, a start whose joint 1 gives no branch inside the limits scans joint 1 from
 *           there outward, q1 +- step, q1 +- 2 step, ... inside its limits [rad].
 *   Returns the index of the first start with a branch inside the limits (the branch nearest the
 *   start, at the joint-1 value nearest the start's, is written to out), or -1.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

enum {
    P_OFF = 0,   /* theta offsets, 7 */
    P_SIN = 7,   /* sin alpha, 7 */
    P_COS = 14,  /* cos alpha, 7 */
    P_A = 21,    /* a, 7 */
    P_D = 28,    /* d, 7 */
    P_LO = 35,   /* lower limits, 7 */
    P_HI = 42,   /* upper limits, 7 */
    P_S3 = 49,   /* shoulder point in frame 3, 3 */
    P_S3_2 = 52, /* its squared norm */
    P_WU = 53,   /* elbow vector u of the wrist centre, 3 */
    P_G = 56,    /* Rx(alpha6) e_z, 3 */
    P_TOOL = 59, /* tool origin in frame 7, 3 */
    P_W7 = 62,   /* wrist centre in frame 7, 3 */
    P_AX7 = 65,  /* (0, sin alpha7, cos alpha7), 3 */
    PARAM_COUNT = 68
};

#define COS_SLACK 1e-12
#define TWO_PI 6.283185307179586

typedef struct {
    double t1, q2, q3, q4, t2, t3, t4;
} Arm;

static int clamp_cos(double *c)
{
    if (*c > 1.0) {
        if (*c > 1.0 + COS_SLACK) return 0;
        *c = 1.0;
    } else if (*c < -1.0) {
        if (*c < -1.0 - COS_SLACK) return 0;
        *c = -1.0;
    }
    return 1;
}

static int inside(const double *P, int i, double q)
{
    return P[P_LO + i] <= q && q <= P[P_HI + i];
}

/* SevenDofIK._arm: branches putting Rz(t4) u (frame 3) on the point pt (frame 0). */
static int arm(const double *P, double q1, const double *pt, const double *u, Arm *out)
{
    const double *S = P + P_SIN, *C = P + P_COS, *off = P + P_OFF, *s3v = P + P_S3;
    double t1 = q1 + off[0];
    double c1 = cos(t1), s1 = sin(t1);
    double a1 = P[P_A + 0];
    double x = pt[0] - a1 * c1, y = pt[1] - a1 * s1, z = pt[2] - P[P_D + 0];
    double xr = c1 * x + s1 * y, yr = c1 * y - s1 * x;
    double dx = xr, dy = C[0] * yr + S[0] * z, dz = C[0] * z - S[0] * yr - P[P_D + 1];
    double ux = u[0], uy = u[1], uz = u[2];
    double sx = s3v[0], sy = s3v[1], sz = s3v[2];
    double p = sx * ux + sy * uy, q = sy * ux - sx * uy;
    double rho = hypot(p, q);
    if (rho < 1e-15) return 0;
    double k = 0.5 * (ux * ux + uy * uy + uz * uz + P[P_S3_2] - dx * dx - dy * dy - dz * dz);
    double cosine = (k - sz * uz) / rho;
    if (!clamp_cos(&cosine)) return 0;
    double phi = atan2(q, p), delta = acos(cosine);
    double s2 = S[1], c2 = C[1], s3 = S[2], c3 = C[2];
    double heading = atan2(dy, dx);
    double t4s[2] = {phi + delta, phi - delta};
    int n4 = delta > 0.0 ? 2 : 1, count = 0;
    if (n4 == 1) t4s[0] = phi;
    for (int i = 0; i < n4; i++) {
        double t4 = t4s[i];
        double q4 = remainder(t4 - off[3], TWO_PI);
        if (!inside(P, 3, q4)) continue;
        double c4 = cos(t4), s4 = sin(t4);
        double vx = ux * c4 - uy * s4 - sx;
        double vy0 = ux * s4 + uy * c4 - sy;
        double vz0 = uz - sz;
        double vy = c3 * vy0 - s3 * vz0, vz = s3 * vy0 + c3 * vz0;
        double pp = s2 * vy, qq = s2 * vx;
        double rho3 = hypot(pp, qq);
        if (rho3 < 1e-15) continue;
        double cos3 = (dz - c2 * vz) / rho3;
        if (!clamp_cos(&cos3)) continue;
        double phi3 = atan2(qq, pp), delta3 = acos(cos3);
        double t3s[2] = {phi3 + delta3, phi3 - delta3};
        int n3 = delta3 > 0.0 ? 2 : 1;
        if (n3 == 1) t3s[0] = phi3;
        for (int j = 0; j < n3; j++) {
            double t3 = t3s[j];
            double q3 = remainder(t3 - off[2], TWO_PI);
            if (!inside(P, 2, q3)) continue;
            double cb = cos(t3), sb = sin(t3);
            double mx = vx * cb - vy * sb;
            double my = c2 * (vx * sb + vy * cb) - s2 * vz;
            double t2 = heading - atan2(my, mx);
            double q2 = remainder(t2 - off[1], TWO_PI);
            if (!inside(P, 1, q2)) continue;
            Arm a = {t1, q2, q3, q4, t2, t3, t4};
            out[count++] = a;
        }
    }
    return count;
}

/* SevenDofIK.pose: joint vectors inside the limits (up to 8) for joint 1 at q1. */
static int pose(const double *P, double q1, const double *W, const double *X7, const double *Z7,
                double (*sol)[7])
{
    Arm arms[4];
    int n = arm(P, q1, W, P + P_WU, arms), count = 0;
    const double *S = P + P_SIN, *C = P + P_COS, *off = P + P_OFF, *g = P + P_G;
    for (int b = 0; b < n; b++) {
        const Arm *a = &arms[b];
        double xx = X7[0], xy = X7[1], xz = X7[2], zx = Z7[0], zy = Z7[1], zz = Z7[2];
        double ts[4] = {a->t1, a->t2, a->t3, a->t4};
        for (int i = 0; i < 4; i++) {
            double ct = cos(ts[i]), st = sin(ts[i]), sa = S[i], ca = C[i], tmp;
            tmp = ct * xx + st * xy;
            xy = ct * xy - st * xx;
            xx = tmp;
            tmp = ca * xy + sa * xz;
            xz = ca * xz - sa * xy;
            xy = tmp;
            tmp = ct * zx + st * zy;
            zy = ct * zy - st * zx;
            zx = tmp;
            tmp = ca * zy + sa * zz;
            zz = ca * zz - sa * zy;
            zy = tmp;
        }
        /* Rz(t5) Rx(alpha5) Rz(t6) g = z4 (SevenDofIK's _rotation_pair). */
        double s5 = S[4], c5 = C[4], s6 = S[5], c6 = C[5];
        double p = s5 * g[1], q = s5 * g[0];
        double rho = hypot(p, q);
        if (rho < 1e-15) continue;
        double cosine = (zz - c5 * g[2]) / rho;
        if (!clamp_cos(&cosine)) continue;
        double phi = atan2(q, p), delta = acos(cosine), heading = atan2(zy, zx);
        double t6s[2] = {phi + delta, phi - delta};
        int n6 = delta > 0.0 ? 2 : 1;
        if (n6 == 1) t6s[0] = phi;
        for (int j = 0; j < n6; j++) {
            double t6 = t6s[j];
            double cb = cos(t6), sb = sin(t6);
            double mx = g[0] * cb - g[1] * sb;
            double my = c5 * (g[0] * sb + g[1] * cb) - s5 * g[2];
            double t5 = heading - atan2(my, mx);
            double q5 = remainder(t5 - off[4], TWO_PI);
            double q6 = remainder(t6 - off[5], TWO_PI);
            if (!(inside(P, 4, q5) && inside(P, 5, q6))) continue;
            double ct = cos(t5), st = sin(t5), tmp;
            double nx = ct * xx + st * xy, ny = ct * xy - st * xx, nz;
            tmp = c5 * ny + s5 * xz;
            nz = c5 * xz - s5 * ny;
            ny = tmp;
            ct = cos(t6);
            st = sin(t6);
            tmp = ct * nx + st * ny;
            ny = ct * ny - st * nx;
            nx = tmp;
            ny = c6 * ny + s6 * nz;
            double q7 = remainder(atan2(ny, nx) - off[6], TWO_PI);
            if (!inside(P, 6, q7)) continue;
            double *s = sol[count++];
            s[0] = q1;
            s[1] = a->q2;
            s[2] = a->q3;
            s[3] = a->q4;
            s[4] = q5;
            s[5] = q6;
            s[6] = q7;
        }
    }
    return count;
}

/* SevenDofIK.elbow_vector: u of the tool origin for the wrist values q5, q6, q7. */
static void elbow_vector(const double *P, double q5, double q6, double q7, double *u)
{
    const double *S = P + P_SIN, *C = P + P_COS, *off = P + P_OFF;
    double x = P[P_TOOL], y = P[P_TOOL + 1], z = P[P_TOOL + 2];
    double qs[3] = {q7, q6, q5};
    for (int k = 0; k < 3; k++) {
        int i = 6 - k;
        double t = qs[k] + off[i];
        double nx = P[P_A + i] + x, ny = C[i] * y - S[i] * z, nz = P[P_D + i] + S[i] * y + C[i] * z;
        double ct = cos(t), st = sin(t);
        x = ct * nx - st * ny;
        y = st * nx + ct * ny;
        z = nz;
    }
    u[0] = P[P_A + 3] + x;
    u[1] = C[3] * y - S[3] * z;
    u[2] = P[P_D + 3] + S[3] * y + C[3] * z;
}

/* A C-contiguous float64 buffer of `obj` (writable if asked); 0 and a Python error otherwise. */
static int get_doubles(PyObject *obj, Py_buffer *view, int writable, const char *name)
{
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0) return 0;
    if (view->format == NULL || strcmp(view->format, "d") != 0 || view->itemsize != sizeof(double)) {
        PyBuffer_Release(view);
        PyErr_Format(PyExc_TypeError, "%s: expected a C-contiguous float64 array", name);
        return 0;
    }
    return 1;
}

static PyObject *first(PyObject *self, PyObject *args)
{
    PyObject *params_obj, *target_obj, *starts_obj, *out_obj;
    Py_buffer params, target, starts, out;
    int mode;
    double step;
    if (!PyArg_ParseTuple(args, "OiOOOd", &params_obj, &mode, &target_obj, &starts_obj, &out_obj,
                          &step))
        return NULL;
    if (!get_doubles(params_obj, &params, 0, "params")) return NULL;
    if (!get_doubles(target_obj, &target, 0, "target")) {
        PyBuffer_Release(&params);
        return NULL;
    }
    if (!get_doubles(starts_obj, &starts, 0, "starts")) {
        PyBuffer_Release(&params);
        PyBuffer_Release(&target);
        return NULL;
    }
    if (!get_doubles(out_obj, &out, 1, "out")) {
        PyBuffer_Release(&params);
        PyBuffer_Release(&target);
        PyBuffer_Release(&starts);
        return NULL;
    }
    long found = -1;
    const char *error = NULL;
    Py_ssize_t need = mode == 0 ? 12 : 3;
    if (params.len != PARAM_COUNT * (Py_ssize_t)sizeof(double)) error = "params: wrong size";
    else if (mode != 0 && mode != 1) error = "mode must be 0 (pose) or 1 (position)";
    else if (target.len != need * (Py_ssize_t)sizeof(double)) error = "target: wrong size";
    else if (starts.ndim != 2 || starts.shape[1] != 7) error = "starts: not k x 7 float64";
    else if (out.len != 7 * (Py_ssize_t)sizeof(double)) error = "out: not 7 float64";
    if (error == NULL) {
        const double *P = params.buf, *T = target.buf, *Q = starts.buf;
        double *result = out.buf;
        Py_ssize_t k = starts.len / (7 * sizeof(double));
        double W[3], X7[3], Z7[3];
        if (mode == 0) {
            const double *R = T + 3, *w7 = P + P_W7, *ax = P + P_AX7;
            for (int i = 0; i < 3; i++) {
                const double *row = R + 3 * i;
                W[i] = T[i] + row[0] * w7[0] + row[1] * w7[1] + row[2] * w7[2];
                X7[i] = row[0];
                Z7[i] = row[1] * ax[1] + row[2] * ax[2];
            }
        }
        for (Py_ssize_t r = 0; r < k && found < 0; r++) {
            double v[7], sol[8][7];
            int n = 0, finite = 1;
            for (int i = 0; i < 7; i++) {
                double x = Q[7 * r + i];
                finite = finite && isfinite(x);
                v[i] = x < P[P_LO + i] ? P[P_LO + i] : (x > P[P_HI + i] ? P[P_HI + i] : x);
            }
            if (!finite) continue; /* a start with a NaN or an infinity has no joint 1 to keep */
            double u[3];
            if (mode == 1) elbow_vector(P, v[4], v[5], v[6], u);
            for (long j = 0; n == 0; j++) {
                int inside_limits = 0;
                for (int sign = 1; sign >= -1 && n == 0; sign -= 2) {
                    if (j == 0 && sign < 0) break;
                    double q1 = v[0] + sign * (double)j * step;
                    if (q1 < P[P_LO] || q1 > P[P_HI]) continue;
                    inside_limits = 1;
                    if (mode == 0) {
                        n = pose(P, q1, W, X7, Z7, sol);
                    } else {
                        Arm arms[4];
                        n = arm(P, q1, T, u, arms);
                        for (int b = 0; b < n; b++) {
                            sol[b][0] = q1;
                            sol[b][1] = arms[b].q2;
                            sol[b][2] = arms[b].q3;
                            sol[b][3] = arms[b].q4;
                            sol[b][4] = v[4];
                            sol[b][5] = v[5];
                            sol[b][6] = v[6];
                        }
                    }
                }
                if (!inside_limits || !(step > 0.0)) break;
            }
            if (n == 0) continue;
            int best = 0;
            double best_d = INFINITY;
            for (int b = 0; b < n; b++) {
                double d = 0.0;
                for (int i = 0; i < 7; i++) d += (sol[b][i] - v[i]) * (sol[b][i] - v[i]);
                if (d < best_d) {
                    best_d = d;
                    best = b;
                }
            }
            for (int i = 0; i < 7; i++) result[i] = sol[best][i];
            found = (long)r;
        }
    }
    PyBuffer_Release(&params);
    PyBuffer_Release(&target);
    PyBuffer_Release(&starts);
    PyBuffer_Release(&out);
    if (error != NULL) {
        PyErr_SetString(PyExc_ValueError, error);
        return NULL;
    }
    return PyLong_FromLong(found);
}

static PyMethodDef methods[] = {
    {"first", first, METH_VARARGS,
     "first(params, mode, target, starts, out, step) -> index of the first start with a branch inside "
     "the limits (written to out), or -1. See ik/seven_dof.py."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_closed7",
                                    "Compiled twin of ik.seven_dof (optional speed-up).", -1,
                                    methods};

PyMODINIT_FUNC PyInit__closed7(void) { return PyModule_Create(&module); }

/*
 * Compiled twin of kin/ik/analytic/seven_r/spherical_shoulder7.py (SphericalShoulder7RIK.first with its
 * branches, the joint-7 scan and the branch nearest a start): the same arithmetic, operation for
 * operation, for speed, except that the angle pairs a limit check drops are dropped before their
 * second angle is computed (rotation_pair_fit in _twin.h). The Python module is the reference
 * and the fallback when this extension is not built; tests/native/test_shoulder7_parity.py compares the
 * two. Angles in radians, lengths in meters.
 *
 * first(params, target, starts, out, step) -> int
 *   params: float64[PARAM_COUNT], SphericalShoulder7RIK.c_params (SHOULDER7_PARAMS below,
 *           exported as LAYOUT);
 *   target: SphericalShoulder7RIK.prepare of a full pose, 12 floats: R_K_J7 row-major (9), then
 *           the shoulder point S seen from J_7 (3);
 *   starts: float64[k, 7], start joint vectors (clipped into the limits here; a row with a value
 *           that is not finite is skipped);
 *   out:    float64[7], receives the solution;
 *   step:   when > 0, a start whose joint 7 gives no branch inside the limits scans joint 7 from
 *           there outward, q7 +- step, q7 +- 2 step, ... inside its limits [rad].
 *   Returns the index of the first start with a branch inside the limits (the branch nearest the
 *   start, at the joint-7 value nearest the start's, is written to out), or -1.
 *
 * first_many(params, targets, starts, out, steps) -> int: first() of N targets at once, each from
 *   its own start (targets float64[N, 12], starts float64[N, 7]), trying the scan steps
 *   (float64[m]) in turn until one gives a branch; out float64[N, 7] receives the rows found
 *   (others untouched). Returns how many were found (first_many_call in _twin.h).
 */
#include "_twin.h"

/*
 * The parameter layout, declared here once. SphericalShoulder7RIK.c_params reads the order,
 * offsets and sizes from LAYOUT (exported below), filling each field by name; a test checks both
 * sides. X(field, size, description)
 */
#define SHOULDER7_PARAMS(X)                                                      \
    X(off, 7, "theta offsets [rad]")                                             \
    X(sin, 8, "sin alpha_i' (index 2 .. 7; 0 and 1 unused)")                     \
    X(cos, 8, "cos alpha_i' (index 2 .. 7; 0 and 1 unused)")                     \
    X(lo, 7, "lower joint limits [rad]")                                         \
    X(hi, 7, "upper joint limits [rad]")                                         \
    X(c7, 3, "wrist point W just before Rz(t7) [m]")                             \
    X(u, 3, "shoulder point S just before Rz(t4) [m]")                           \
    X(w4, 3, "wrist point W in J_4 [m]")                                         \
    X(elbow, 3, "p, q, k of the elbow equation p cos t4 + q sin t4 = k - |S-W|^2/2") \
    X(reach2, 2, "|S - W|^2 over joint 4's limits, min and max [m^2]")           \
    X(m7, 9, "rotation of M_7, row-major")                                      \
    X(arc, 24, "joints 1-6: cos, sin of t at the limits' middle, cos of half their span; 1 if wide")

TWIN_PARAMS(SHOULDER7_PARAMS)
#define BRANCHES 8

/* _into_limits: q + 2 pi k inside [lo[j], hi[j]] nearest near[j], written to *out; 0 if none. */
static int into_limits(const Params *P, int j, double q, const double *near, double *out)
{
    double low = P->lo[j], high = P->hi[j], n = near[j];
    q = n + turn_remainder(q - n);
    if (low <= q && q <= high) {
        *out = q;
        return 1;
    }
    double up = q + TWO_PI, down = q - TWO_PI;
    int down_in = low <= down && down <= high;
    if (low <= up && up <= high && !(down_in && n - down < up - n)) {
        *out = up;
        return 1;
    }
    if (down_in) {
        *out = down;
        return 1;
    }
    return 0;
}

/* _back: R_K_J6 Rz(-t6) Rx(alpha)^T Rz(-t5) (x, y, z); turn = (cos t5, sin t5, sin alpha,
   cos alpha, cos t6, sin t6), k6 = R_K_J6 row-major. */
static void back(const double *k6, const double *turn, double x, double y, double z, double *r)
{
    double c5 = turn[0], s5 = turn[1], sa = turn[2], ca = turn[3], c6 = turn[4], s6 = turn[5];
    double tmp;
    tmp = c5 * x + s5 * y;
    y = c5 * y - s5 * x;
    x = tmp;
    tmp = ca * y + sa * z;
    z = ca * z - sa * y;
    y = tmp;
    tmp = c6 * x + s6 * y;
    y = c6 * y - s6 * x;
    x = tmp;
    for (int i = 0; i < 3; i++) r[i] = k6[3 * i] * x + k6[3 * i + 1] * y + k6[3 * i + 2] * z;
}

/* joint j's arc (j = 0..5: joints 1-6) */
#define ARC(j) (P->arc + 4 * (j))

/*
 * A test before branches()'s angles (not in the Python module: the same answers). Most joint-7
 * values a scan visits inside joint 4's reach give no branch: a joint lands outside its limits.
 * branches_may_fit() follows the branches as directions (cos, sin: square roots and products
 * instead of atan2, acos, sin and cos; the helpers in _twin.h) and the joint ranges as arcs,
 * and says 0 only when every branch has a joint outside its arc, widened by a slack; where a
 * direction could not be trusted to well within it (the guards), it says 1 and the exact path
 * decides. Worst cases under the guards: joints 4 and 6 off by 5e-10 rad, joint 5 by 2e-8,
 * joints 1-3 by 3e-5 / rho2 rad (rho2 = |sin alpha3' sin alpha4'|, 1 for Panda and xArm7; the
 * shoulder is not tested below CHAIN_RHO_MIN); errors of 1e-12 are usual. The tests compare the
 * twin with the Python module at the limits' edges.
 */
static int branches_may_fit(const Params *P, double ke, const double *v6, const double *k6)
{
    const double *s = P->sin, *c = P->cos, *u = P->u, *w4 = P->w4;
    double c4s[2], s4s[2], c6s[2], s6s[2], c2s[2], s2s[2];
    int n4 = root_directions(P->elbow[0], P->elbow[1], ke, c4s, s4s);
    if (n4 < 0) return 1;
    int shoulder = fabs(s[2] * s[3]) >= CHAIN_RHO_MIN; /* joint 2's equation: test joints 1-3 */
    for (int e = 0; e < n4; e++) {
        double c4 = c4s[e], s4 = s4s[e];
        if (!arc_admits(ARC(3), c4, s4, ARC_SLACK)) continue;
        double vx = c4 * u[0] + s4 * u[1] - w4[0], vy = c4 * u[1] - s4 * u[0] - w4[1];
        double vz = u[2] - w4[2];
        double d[3] = {vx, c[5] * vy + s[5] * vz, c[5] * vz - s[5] * vy};
        int n6 = root_directions(s[6] * v6[1], s[6] * v6[0], d[2] - c[6] * v6[2], c6s, s6s);
        if (n6 < 0) return 1;
        double zy = c4 * s[4], zz = c[4];
        double z4[3] = {s4 * s[4], c[5] * zy + s[5] * zz, c[5] * zz - s[5] * zy};
        double x4[3] = {c4, -c[5] * s4, s[5] * s4};
        for (int w = 0; w < n6; w++) {
            double c6 = c6s[w], s6 = s6s[w], c5, s5;
            if (!arc_admits(ARC(5), c6, s6, ARC_SLACK)) continue;
            double mx = v6[0] * c6 - v6[1] * s6;
            double my = c[6] * (v6[0] * s6 + v6[1] * c6) - s[6] * v6[2];
            if (!angle_difference(d[0], d[1], SHORT_XY, mx, my, SHORT_XY, &c5, &s5)) return 1;
            if (!arc_admits(ARC(4), c5, s5, CHAIN_SLACK)) continue;
            if (!shoulder) return 1;
            double turn[6] = {c5, s5, s[6], c[6], c6, s6}, z[3], x[3];
            back(k6, turn, z4[0], z4[1], z4[2], z);
            back(k6, turn, x4[0], x4[1], x4[2], x);
            double v3[3] = {0.0, -s[3], c[3]};
            int n2 = root_directions(s[2] * v3[1], s[2] * v3[0], z[2] - c[2] * v3[2], c2s, s2s);
            if (n2 < 0) return 1;
            for (int h = 0; h < n2; h++) {
                double c2 = c2s[h], s2 = s2s[h], c1, s1, c3, s3;
                if (!arc_admits(ARC(1), c2, s2, CHAIN_SLACK)) continue;
                double ax = v3[0] * c2 - v3[1] * s2;
                double ay = c[2] * (v3[0] * s2 + v3[1] * c2) - s[2] * v3[2];
                if (!angle_difference(z[0], z[1], SHORT_UNIT, ax, ay, SHORT_UNIT, &c1, &s1))
                    return 1;
                if (!arc_admits(ARC(0), c1, s1, CHAIN_SLACK)) continue;
                double nx = c1 * x[0] + s1 * x[1], ny = c1 * x[1] - s1 * x[0], nz = x[2], tmp;
                tmp = c[2] * ny + s[2] * nz;
                nz = c[2] * nz - s[2] * ny;
                ny = tmp;
                tmp = c2 * nx + s2 * ny;
                ny = c2 * ny - s2 * nx;
                nx = tmp;
                ny = c[3] * ny + s[3] * nz;
                if (!angle_difference(nx, ny, SHORT_UNIT, 1.0, 0.0, 0.0, &c3, &s3)) return 1;
                if (arc_admits(ARC(2), c3, s3, CHAIN_SLACK)) return 1;
            }
        }
    }
    return 0;
}

/* SphericalShoulder7RIK.branches with the fit of first (each joint into its limits, nearest the
   start `near`): joint vectors inside the limits (up to 8) for joint 7 at q7, in slot order;
   c7, s7: cos, sin of t7 = q7 + offset (try_q7 has them). */
static int branches(const Params *P, const double *T, double q7, double c7, double s7,
                    const double *near, double (*sol)[7])
{
    const double *s = P->sin, *c = P->cos, *off = P->off, *a = P->m7;
    double r00 = T[0], r01 = T[1], r02 = T[2], r10 = T[3], r11 = T[4], r12 = T[5];
    double r20 = T[6], r21 = T[7], r22 = T[8], ex = T[9], ey = T[10], ez = T[11];
    double wx = P->c7[0], wy = P->c7[1], wz = P->c7[2];
    /* S - W before Rz(t7): Rz(t7) e - c7; in J_6: M_7's rotation of it. */
    double rx = c7 * ex - s7 * ey - wx, ry = s7 * ex + c7 * ey - wy, rz = ez - wz;
    double ux = P->u[0], uy = P->u[1], uz = P->u[2];
    double w4x = P->w4[0], w4y = P->w4[1], w4z = P->w4[2];
    double distance2 = rx * rx + ry * ry + rz * rz;
    double v6[3] = {a[0] * rx + a[1] * ry + a[2] * rz, a[3] * rx + a[4] * ry + a[5] * rz,
                    a[6] * rx + a[7] * ry + a[8] * rz};
    /* R_K_J6 = R_K_J7 Rz(-t7) M_7^T (rows). */
    double b00 = r00 * c7 - r01 * s7, b01 = r00 * s7 + r01 * c7;
    double b10 = r10 * c7 - r11 * s7, b11 = r10 * s7 + r11 * c7;
    double b20 = r20 * c7 - r21 * s7, b21 = r20 * s7 + r21 * c7;
    double k6[9] = {
        b00 * a[0] + b01 * a[1] + r02 * a[2], b00 * a[3] + b01 * a[4] + r02 * a[5],
        b00 * a[6] + b01 * a[7] + r02 * a[8], b10 * a[0] + b11 * a[1] + r12 * a[2],
        b10 * a[3] + b11 * a[4] + r12 * a[5], b10 * a[6] + b11 * a[7] + r12 * a[8],
        b20 * a[0] + b21 * a[1] + r22 * a[2], b20 * a[3] + b21 * a[4] + r22 * a[5],
        b20 * a[6] + b21 * a[7] + r22 * a[8],
    };
    if (directions_on && !branches_may_fit(P, P->elbow[2] - 0.5 * distance2, v6, k6)) return 0;
    double elbows[2];
    int n4 = harmonic_roots(P->elbow[0], P->elbow[1], P->elbow[2] - 0.5 * distance2, elbows);
    if (n4 == 0) return 0;
    double v3[3] = {0.0, -s[3], c[3]};
    int count = 0;
    for (int e = 0; e < n4; e++) {
        double t4 = elbows[e], q[7];
        if (!into_limits(P, 3, t4 - off[3], near, &q[3])) continue;
        double c4 = cos(t4), s4 = sin(t4);
        /* S - W in J_4 (Rz(-t4) u - w4), then through Rx(alpha_5')^T. */
        double vx = c4 * ux + s4 * uy - w4x, vy = c4 * uy - s4 * ux - w4y, vz = uz - w4z;
        double d[3] = {vx, c[5] * vy + s[5] * vz, c[5] * vz - s[5] * vy};
        double zy = c4 * s[4], zz = c[4];
        double z4[3] = {s4 * s[4], c[5] * zy + s[5] * zz, c[5] * zz - s[5] * zy};
        double x4[3] = {c4, -c[5] * s4, s[5] * s4};
        double t5s[2], t6s[2], c6s[2], s6s[2]; /* c6s, s6s: cos, sin of t6s */
        int n6 = rotation_pair_fit(s[6], c[6], v6, d, t5s, t6s, c6s, s6s, off[5], P->lo[5],
                                   P->hi[5]);
        for (int w = 0; w < n6; w++) {
            double t5 = t5s[w], t6 = t6s[w];
            if (!into_limits(P, 4, t5 - off[4], near, &q[4])) continue;
            if (!into_limits(P, 5, t6 - off[5], near, &q[5])) continue;
            double turn[6] = {cos(t5), sin(t5), s[6], c[6], c6s[w], s6s[w]};
            double z[3], x[3];
            back(k6, turn, z4[0], z4[1], z4[2], z);
            back(k6, turn, x4[0], x4[1], x4[2], x);
            double t1s[2], t2s[2], c2s[2], s2s[2]; /* c2s, s2s: cos, sin of t2s */
            int n2 = rotation_pair_fit(s[2], c[2], v3, z, t1s, t2s, c2s, s2s, off[1], P->lo[1],
                                       P->hi[1]);
            for (int h = 0; h < n2; h++) {
                double t1 = t1s[h], t2 = t2s[h];
                if (!into_limits(P, 0, t1 - off[0], near, &q[0])) continue;
                if (!into_limits(P, 1, t2 - off[1], near, &q[1])) continue;
                /* t3: Rx3^T Rz(-t2) Rx2^T Rz(-t1) x_3 = (cos t3, sin t3, 0). */
                double ct = cos(t1), st = sin(t1), tmp;
                double nx = ct * x[0] + st * x[1], ny = ct * x[1] - st * x[0], nz = x[2];
                tmp = c[2] * ny + s[2] * nz;
                nz = c[2] * nz - s[2] * ny;
                ny = tmp;
                ct = c2s[h];
                st = s2s[h];
                tmp = ct * nx + st * ny;
                ny = ct * ny - st * nx;
                nx = tmp;
                ny = c[3] * ny + s[3] * nz;
                if (!into_limits(P, 2, atan2(ny, nx) - off[2], near, &q[2])) continue;
                q[6] = q7;
                memcpy(sol[count++], q, sizeof q);
            }
        }
    }
    return count;
}

/* The 12 floats of a prepared target (a tuple or list); 0 and a Python error otherwise. */
static int get_target(PyObject *obj, double *T)
{
    PyObject *seq = PySequence_Fast(obj, "target: expected a sequence of 12 floats");
    if (seq == NULL) return 0;
    if (PySequence_Fast_GET_SIZE(seq) != 12) {
        Py_DECREF(seq);
        PyErr_SetString(PyExc_ValueError, "target: expected 12 floats");
        return 0;
    }
    PyObject **items = PySequence_Fast_ITEMS(seq);
    for (int i = 0; i < 12; i++) {
        T[i] = PyFloat_AsDouble(items[i]);
        if (T[i] == -1.0 && PyErr_Occurred()) {
            Py_DECREF(seq);
            return 0;
        }
    }
    Py_DECREF(seq);
    return 1;
}

/* The branch of sol[0 .. n) nearest v (first of equals) into result. */
/* Branches for joint 7 at q7, or 0 without solving when |S - W|^2 is outside joint 4's range. */
static int try_q7(const Params *P, const double *T, const double *reach, double q7,
                  const double *v, double (*sol)[7])
{
    double t7 = q7 + P->off[6];
    double c7 = cos(t7), s7 = sin(t7); /* branches() takes them (the same values) */
    double distance2 = reach[0] - reach[1] * c7 - reach[2] * s7;
    if (!(P->reach2[0] <= distance2 && distance2 <= P->reach2[1])) return 0;
    return branches(P, T, q7, c7, s7, v, sol);
}

/* The first of the k starts Q (rows of 7) with a branch inside the limits for the prepared target
   T: its branch nearest it into result, and its index; -1 when none (result untouched). */
static long first_start(const void *params, int mode, const double *T, const double *Q,
                        Py_ssize_t k, double step, double *result)
{
    const Params *P = params;
    (void)mode; /* full poses only */
    /* |S - W|^2 at t7 is |e|^2 + |c7|^2 - 2 c7 . Rz(t7) e = base2 - cx cos t7 - cy sin t7. */
    double ex = T[9], ey = T[10], ez = T[11];
    double wx = P->c7[0], wy = P->c7[1], wz = P->c7[2];
    double reach[3] = {
        ex * ex + ey * ey + ez * ez + wx * wx + wy * wy + wz * wz - 2.0 * wz * ez,
        2.0 * (wx * ex + wy * ey),
        2.0 * (wy * ex - wx * ey),
    };
    double low7 = P->lo[6], high7 = P->hi[6];
    for (Py_ssize_t r = 0; r < k; r++) {
        double v[7], sol[BRANCHES][7];
        int n = 0;
        if (!clip_start(Q + 7 * r, P->lo, P->hi, v)) continue;
        /* subproblems.scan: v7, then v7 + j step and v7 - j step inside the limits. */
        double value = v[6];
        n = try_q7(P, T, reach, value, v, sol);
        if (n == 0 && step > 0.0) {
            for (double j = 1.0; n == 0; j += 1.0) {
                double up = value + j * step, down = value - j * step;
                if (up > high7 && down < low7) break;
                if (low7 <= up && up <= high7) n = try_q7(P, T, reach, up, v, sol);
                if (n == 0 && low7 <= down && down <= high7)
                    n = try_q7(P, T, reach, down, v, sol);
            }
        }
        if (n == 0) continue;
        nearest((const double (*)[7])sol, n, v, result);
        return (long)r;
    }
    return -1;
}

#define SEEDED_POINTS 0 /* first_start takes full poses only */
#include "_seeded7.h"

/* SphericalShoulder7RIK.prepare in C (full poses): R_K_J7 = K^T R M^T (9) and S seen from J_7,
   R_K_J7^T (S - K^T (p - k)) + m (3), S the shoulder point (K, k: the structure's base frame;
   M, m: its tool). */
static void prepare_seeded(const Seed *S, int mode, const double *p, const double *r, double *T)
{
    (void)mode; /* full poses only: the caller never asks a point */
    double x[3], g[3];
    frame_rotation(S, r, T);
    frame_point(S, p, x);
    for (int i = 0; i < 3; i++) g[i] = S->point[i] - x[i];
    for (int j = 0; j < 3; j++)
        T[9 + j] = T[j] * g[0] + T[3 + j] * g[1] + T[6 + j] * g[2] + S->end_t[j];
}

/* The branches at q7 of the form without limits (all_branches in _branches7.h): each joint
   into [-pi, pi] (near 0). */
static int branches_at_value(const Params *P, const double *T, double q7, double (*sol)[7])
{
    static const double zero[7] = {0.0};
    double t7 = q7 + P->off[6];
    return branches(P, T, q7, cos(t7), sin(t7), zero, sol);
}

#include "_branches7.h"

static PyObject *first(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *objs[3], *target_obj;
    static const char *const names[3] = {"params", "starts", "out"};
    static const int writable[3] = {0, 0, 1};
    Py_buffer views[3];
    double step, T[12];
    if (!PyArg_ParseTuple(args, "OOOOd", &objs[0], &target_obj, &objs[1], &objs[2], &step))
        return NULL;
    if (!get_target(target_obj, T)) return NULL;
    if (!get_buffers(3, objs, views, writable, names)) return NULL;
    Py_buffer params = views[0], starts = views[1], out = views[2];
    long found = -1;
    const char *error = check_arrays(&params, PARAM_COUNT, &starts, &out);
    if (error == NULL)
        found = first_start(params.buf, 0, T, starts.buf, starts.shape[0], step, out.buf);
    return first_result(3, views, error, found);
}

static PyObject *first_many(PyObject *self, PyObject *args)
{
    (void)self;
    return first_many_call(args, 0, PARAM_COUNT, first_start);
}

static PyMethodDef methods[] = {
    {"first", first, METH_VARARGS,
     "first(params, target, starts, out, step) -> index of the first start with a branch inside "
     "the limits (written to out), or -1. See kin/ik/analytic/seven_r/spherical_shoulder7.py."},
    {"first_many", first_many, METH_VARARGS, FIRST_MANY_DOC},
    {"seeded", (PyCFunction)(void (*)(void))seeded, METH_FASTCALL, SEEDED_DOC},
    {"seeded_many", seeded_many, METH_VARARGS, SEEDED_MANY_DOC},
    {"all_branches", (PyCFunction)(void (*)(void))all_branches, METH_FASTCALL, ALL_BRANCHES_DOC},
    {"sift_rows", (PyCFunction)(void (*)(void))sift_rows, METH_FASTCALL, SIFT_ROWS_DOC},
    {"skips", set_skips, METH_O, SKIPS_DOC},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_shoulder7",
    "Compiled twin of kin.ik.analytic.spherical_shoulder7 (optional speed-up).", -1, methods, NULL,
    NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__shoulder7(void)
{
    if (results_init() < 0) return NULL;
    PyObject *m = twin_module(&module, FIELDS, sizeof FIELDS / sizeof FIELDS[0], PARAM_COUNT);
    if (m != NULL && add_layout(m, "SEED_LAYOUT", SEED_FIELDS, sizeof SEED_FIELDS / sizeof SEED_FIELDS[0]) < 0)
        Py_CLEAR(m);
    return m;
}

/*
 * Compiled twin of the free-angle walk of kin/ik/analytic/planar/free_angle.py (optional: without
 * it the Python walk runs, with the same answer; tests/native/test_pitch_sweep.py holds them to it).
 *
 * A position on a planar 3R chain (a SCARA-like arm of three parallel revolute axes, or the pitch
 * chain of a yaw_planar arm) leaves the last link's angle psi free. When the seed's psi has no
 * branch inside the joint limits, free_angle_branches walks psi in 10-degree steps away from the
 * seed's (+1, -1, +2, -2, ... steps), and from the first step with a branch inside the limits back
 * in 1-degree steps over the 10 degrees before it (nearest the seed's first). One question here:
 * the first psi of that walk with a branch inside the limits (NaN: no 10-degree step has one).
 * The arithmetic is PlaneChain.solve_angle's and row_inside's, operation for operation, with
 * Python's float remainder (the sign of the divisor), so that the psi is the Python walk's.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>

#define TURN (2.0 * M_PI)
#define COARSE_STEPS 36
#define SWEEP_STEPS 360
#define LIMIT_SLACK 1e-10
#define MAX_POINTS 4

/* The chain and the points: l1x l1y l2x l2y l3x l3y rho centre lengths s1 s2 s3, lower 1-3,
   upper 1-3, then (tx, ty) per point (the target in the plane's coordinates). */
typedef struct {
    double l1x, l1y, l2x, l2y, l3x, l3y, rho, centre, lengths;
    double sign[3], lower[3], upper[3];
    double tx[MAX_POINTS], ty[MAX_POINTS];
    int points;
} Chain;

/* Python's float remainder x % y (y > 0 here): the result has the sign of y. */
static double py_mod(double x, double y)
{
    double mod = fmod(x, y);
    if (mod != 0.0) {
        if ((y < 0.0) != (mod < 0.0)) mod += y;
    } else {
        mod = copysign(0.0, y);
    }
    return mod;
}

/* row_inside of one revolute value: a 2 pi copy of it inside [lower, upper] (NaN: outside). */
static int value_inside(double value, double lower, double upper)
{
    double copy = lower + py_mod(value - lower, TURN);
    return lower - LIMIT_SLACK <= copy && copy <= upper + LIMIT_SLACK;
}

/* Whether one of the two elbow branches of one point at psi is inside the limits. */
static int point_inside(const Chain *c, double tx, double ty, double psi)
{
    double cp = cos(psi), sp = sin(psi);
    double wx = tx - (cp * c->l3x - sp * c->l3y);
    double wy = ty - (sp * c->l3x + cp * c->l3y);
    if (c->rho < 1e-15 || !(fabs(wx) < 1e150 && fabs(wy) < 1e150)) return 0;
    double cosine = (wx * wx + wy * wy - c->lengths) / (2.0 * c->rho);
    if (fabs(cosine) > 1.0 + 1e-12) return 0;
    double spread = acos(cosine > 1.0 ? 1.0 : (cosine < -1.0 ? -1.0 : cosine));
    double toward = atan2(wy, wx);
    for (int k = 0; k < 2; k++) {
        double beta = k == 0 ? c->centre + spread : c->centre - spread;
        double cb = cos(beta), sb = sin(beta);
        double phi1 = toward - atan2(c->l1y + sb * c->l2x + cb * c->l2y,
                                     c->l1x + cb * c->l2x - sb * c->l2y);
        double phis[3] = {phi1, phi1 + beta, psi};
        double previous = 0.0;
        int inside = 1;
        for (int j = 0; j < 3 && inside; j++) {
            double q = py_mod(c->sign[j] * (phis[j] - previous) + M_PI, TURN) - M_PI;
            inside = value_inside(q, c->lower[j], c->upper[j]);
            previous = phis[j];
        }
        if (inside) return 1;
    }
    return 0;
}

static int any_inside(const Chain *c, double psi)
{
    for (int i = 0; i < c->points; i++)
        if (point_inside(c, c->tx[i], c->ty[i], psi)) return 1;
    return 0;
}

/* The walk: the first psi with a branch inside the limits, NaN when no 10-degree step has one. */
static double walk(const Chain *c, double start)
{
    double coarse = TURN / COARSE_STEPS, fine = TURN / SWEEP_STEPS, hit = NAN;
    for (int n = 0; n < COARSE_STEPS - 1; n++) {
        int k = n / 2 + 1;
        double angle = start + (double)(n % 2 == 0 ? k : -k) * coarse;
        if (any_inside(c, angle)) {
            hit = angle;
            break;
        }
    }
    if (isnan(hit)) return hit;
    int reach = (int)nearbyint(fabs(hit - start) / TURN * SWEEP_STEPS);
    int first = reach - SWEEP_STEPS / COARSE_STEPS + 1;
    for (int k = first > 1 ? first : 1; k < reach; k++) {
        for (int side = 0; side < 2; side++) {
            double angle = start + (double)(side == 0 ? k : -k) * fine;
            if (any_inside(c, angle)) return angle;
        }
    }
    return hit;
}

static PyObject *first_inside(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "first_inside(start, chain) takes 2 arguments");
        return NULL;
    }
    double start = PyFloat_AsDouble(args[0]);
    if (start == -1.0 && PyErr_Occurred()) return NULL;
    PyObject *seq = PySequence_Fast(args[1], "chain must be a sequence of floats");
    if (seq == NULL) return NULL;
    Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
    if (n < 18 || (n - 18) % 2 != 0 || (n - 18) / 2 > MAX_POINTS) {
        Py_DECREF(seq);
        PyErr_SetString(PyExc_ValueError, "chain: 18 floats and up to 4 (tx, ty) pairs");
        return NULL;
    }
    double v[18 + 2 * MAX_POINTS];
    for (Py_ssize_t i = 0; i < n; i++) {
        v[i] = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(seq, i));
        if (v[i] == -1.0 && PyErr_Occurred()) {
            Py_DECREF(seq);
            return NULL;
        }
    }
    Py_DECREF(seq);
    Chain c = {v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8],
               {v[9], v[10], v[11]}, {v[12], v[13], v[14]}, {v[15], v[16], v[17]},
               {0}, {0}, (int)((n - 18) / 2)};
    for (int i = 0; i < c.points; i++) {
        c.tx[i] = v[18 + 2 * i];
        c.ty[i] = v[19 + 2 * i];
    }
    return PyFloat_FromDouble(walk(&c, start));
}

static PyMethodDef methods[] = {
    {"first_inside", (PyCFunction)(void (*)(void))first_inside, METH_FASTCALL,
     "first_inside(start, chain) -> the first psi [rad] of the 10- then 1-degree walk from start "
     "with a branch inside the limits, NaN when no 10-degree step has one. chain: l1x l1y l2x l2y "
     "l3x l3y rho centre lengths, the 3 signs, lower 1-3, upper 1-3, then (tx, ty) per point. "
     "See kin/ik/analytic/planar/free_angle.py."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_pitch_sweep",
                                    "Compiled twin of the free-angle walk (optional speed-up).",
                                    -1, methods};

PyMODINIT_FUNC PyInit__pitch_sweep(void) { return PyModule_Create(&module); }

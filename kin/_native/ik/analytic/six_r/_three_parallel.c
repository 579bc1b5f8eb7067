/*
 * Compiled twin of the three-parallel family (kin/ik/analytic/six_r/three_parallel.py and its
 * NumPy algorithm three_parallel_batch.py), both of its cases: intersecting (axes 5 and 6 meet,
 * a5 = 0: the UR arms, URWrist6R, "ur_wrist") and general (a5 != 0). The 8 branches of a target,
 * the same steps as the NumPy form's (_intersecting_slots_batch or _general_slots_batch, then
 * _arm_batch) in the same order, the general case's quartic in t1 by _trig_quartic.h; with verify
 * (each branch moved into the limits and measured by the table's DH product, _six_r_twin.h). The
 * NumPy form is the reference and the fallback when this extension is not built;
 * tests/native/test_six_r_twins.py (the UR case) and tests/native/test_six_r_family_twins.py (the general case)
 * compare the two. Angles in radians, lengths in meters.
 */
#include "_six_r_twin.h"

#include "_trig_quartic.h"

/* The parameter layout (ThreeParallel6R.c_fields fills it by name from LAYOUT). */
#define THREE_PARALLEL_PARAMS(X)                                                \
    FRAME_PARAMS(X)                                                             \
    X(family, 1, "0: intersecting (a5 = 0, the UR case), 1: general")           \
    X(k, 6, "ThreeParallel6R._k: sin, cos of alpha1, alpha4, alpha5")           \
    X(classic, 1, "1 when both wrist twists are +-90 deg")                      \
    X(len, 9, "a1, d1, a2, a3, lateral h, a4, d5, a5, d6 [m]")                  \
    X(off, 6, "theta offsets [rad]")

TWIN_PARAMS(THREE_PARALLEL_PARAMS)

/* Steps 2 and 3 up to the arm plane (_arm_batch): t6 [rad] turning (sa4 s5, ca5 sa4 c5 + sa5 ca4)
   onto z1 seen in frame 6, (x6, y6) (free + theta6 where |(x6, y6)| = xy6 vanishes: _six_r.SINGULAR); then phi =
   t2 + t3 + t4 [rad] from R_0_6 (row-major r), the axes x1 = (ct, st, 0) and y1. */
static inline double wrist_t6(const Params *P, double x6, double y6, double xy6, double cos5,
                              double st5, double free)
{
    const double s4 = P->k[2], c4 = P->k[3], s5a = P->k[4], c5a = P->k[5];
    if (xy6 <= 1e-12) return free + P->off[5]; /* _six_r.SINGULAR; xy6 = |(x6, y6)| */
    double vx = s4 * st5, vy = c5a * s4 * cos5 + s5a * c4;
    return atan2(vy, vx) - atan2(y6, x6);
}

static inline double arm_phi(const Params *P, const double *r, double ct, double st,
                             const double y1[3], double cos5, double st5, double t6)
{
    const double s5a = P->k[4], c5a = P->k[5];
    double ct6 = cos(t6), st6 = sin(t6);
    double xi0 = cos5 * ct6 - st5 * c5a * st6;
    double xi1 = -cos5 * st6 - st5 * c5a * ct6;
    double xi2 = s5a * st5;
    double rx = r[0] * xi0 + r[1] * xi1 + r[2] * xi2;
    double ry = r[3] * xi0 + r[4] * xi1 + r[5] * xi2;
    double rz = r[6] * xi0 + r[7] * xi1 + r[8] * xi2;
    return atan2(y1[0] * rx + y1[1] * ry + y1[2] * rz, ct * rx + st * ry);
}

/* The intersecting case (_intersecting_slots_batch, then _arm_batch): joint 1 by an arcsine,
   the wrist's cos t5 by B(t1); rows 4 shoulder + 2 wrist + elbow. */
static void intersecting_rows(const Params *P, const double *p, const double *r, double free,
                              double out[BRANCHES][JOINTS])
{
    const double s1 = P->k[0], c1 = P->k[1], s4 = P->k[2], c4 = P->k[3], s5a = P->k[4];
    const double c5a = P->k[5];
    const int classic = P->classic[0] != 0.0;
    const double a1 = P->len[0], d1 = P->len[1], a2 = P->len[2], a3 = P->len[3];
    const double h = P->len[4], ex = P->len[5], ey = -s4 * P->len[6], d6 = P->len[8];
    const double *o = P->off;
    for (int b = 0; b < BRANCHES; b++)
        for (int j = 0; j < JOINTS; j++) out[b][j] = NAN;
    /* 1. joint 1 from p5 */
    double px = p[0] - d6 * r[2], py = p[1] - d6 * r[5], pz = p[2] - d6 * r[8];
    double rho = hypot(px, py);
    if (rho == 0.0) return;
    double k = (c1 * (pz - d1) - h) / (s1 * rho);
    if (!clamp_cos(&k)) return;
    double beta = atan2(py, px), asin_k = asin(k);
    double two_a2a3 = 2.0 * a2 * a3, base_sq = a2 * a2 + a3 * a3;
    for (int shoulder = 0; shoulder < 2; shoulder++) {
        double t1 = shoulder == 0 ? beta - asin_k : beta - M_PI + asin_k;
        double ct = cos(t1), st = sin(t1);
        double y1[3] = {-c1 * st, c1 * ct, s1}, z1[3] = {s1 * st, -s1 * ct, c1};
        /* 2. z1 in frame 6 */
        double x6 = r[0] * z1[0] + r[3] * z1[1] + r[6] * z1[2];
        double y6 = r[1] * z1[0] + r[4] * z1[1] + r[7] * z1[2];
        double w = r[2] * z1[0] + r[5] * z1[1] + r[8] * z1[2];
        double cos5 = (c4 * c5a - w) / (s4 * s5a), xy6 = hypot(x6, y6), sin5;
        if (classic) {
            sin5 = xy6;
        } else {
            if (!clamp_cos(&cos5)) continue;
            sin5 = sqrt(1.0 - cos5 * cos5);
        }
        double qx = px - a1 * ct, qy = py - a1 * st, qz = pz - d1;
        double ax = ct * qx + st * qy;
        double ay = y1[0] * qx + y1[1] * qy + y1[2] * qz;
        for (int wrist = 0; wrist < 2; wrist++) {
            double st5 = wrist == 0 ? sin5 : -sin5;
            double t5 = atan2(st5, cos5), t6 = wrist_t6(P, x6, y6, xy6, cos5, st5, free);
            /* 3. phi */
            double phi = arm_phi(P, r, ct, st, y1, cos5, st5, t6), cp = cos(phi), sp = sin(phi);
            double bx = ax - (cp * ex - sp * ey), by = ay - (sp * ex + cp * ey);
            double cos3 = (bx * bx + by * by - base_sq) / two_a2a3;
            if (!clamp_cos(&cos3)) continue;
            double sin3 = sqrt(1.0 - cos3 * cos3), heading = atan2(by, bx);
            double q1 = wrap(t1 - o[0]), q5 = wrap(t5 - o[4]), q6 = wrap(t6 - o[5]);
            int index = 4 * shoulder + 2 * wrist;
            /* Elbow down negates st3: atan2 is odd in its first argument (exactly, in IEEE
               arithmetic), so both elbows share the two atan2 of elbow up. */
            double t3_up = atan2(sin3, cos3), lift = atan2(a3 * sin3, a2 + a3 * cos3);
            for (int elbow = 0; elbow < 2; elbow++) {
                double t3 = elbow == 0 ? t3_up : -t3_up;
                double t2 = elbow == 0 ? heading - lift : heading + lift;
                double t4 = phi - t2 - t3;
                double *row = out[index + elbow];
                row[0] = q1;
                row[1] = wrap(t2 - o[1]);
                row[2] = wrap(t3 - o[2]);
                row[3] = wrap(t4 - o[3]);
                row[4] = q5;
                row[5] = q6;
            }
        }
    }
}

/* u = u0 + uc c1 + us s1, v likewise, and their rounding scales (ThreeParallelBatch._uv). */
typedef struct {
    double u0, uc, us, v0, vc, vs, su, sv, reach;
} UV;

/* ThreeParallelBatch._residual: E(t1), dE/dt1, the bound on |E| of a root, u, v. */
static void residual(const void *ctx, double t1, double out[5])
{
    const UV *q = ctx;
    double c = cos(t1), s = sin(t1);
    double u = q->u0 + q->uc * c + q->us * s, v = q->v0 + q->vc * c + q->vs * s;
    out[0] = u * u + v * v - 1.0;
    out[1] = 2.0 * (u * (q->us * c - q->uc * s) + v * (q->vs * c - q->vc * s));
    out[2] = q->reach + 16.0 * QUARTIC_EPS * (fabs(u) * q->su + fabs(v) * q->sv + 1.0);
    out[3] = u;
    out[4] = v;
}

/* The slots (t1, cos t5, sin t5) of the real roots of E(t1), ascending q1, then NaN. */
static void general_slots(const Params *P, const double w[3], const double n[3],
                          double slots[4][3])
{
    const double s1 = P->k[0], c1 = P->k[1], s4 = P->k[2], c4 = P->k[3], s5 = P->k[4];
    const double c5 = P->k[5], d1 = P->len[1], lateral = P->len[4], a5 = P->len[7];
    double ka = s4 * a5, kb = s4 * s5;
    double su = fabs(s1) * (fabs(w[0]) + fabs(w[1])) + fabs(c1) * (fabs(w[2]) + fabs(d1)) +
                fabs(lateral);
    double sv = fabs(s1) * (fabs(n[0]) + fabs(n[1])) + fabs(c1 * n[2]) + fabs(c4 * c5);
    UV q = {(c1 * (w[2] - d1) - lateral) / ka, -s1 * w[1] / ka, s1 * w[0] / ka,
            (c4 * c5 - c1 * n[2]) / kb, s1 * n[1] / kb, -s1 * n[0] / kb, su / fabs(ka),
            sv / fabs(kb), 2.0 * 1e-10 / fmax(fabs(s4 * a5), fabs(s4 * s5))}; /* REACH_TOL */
    double h0 = q.u0 * q.u0 + q.v0 * q.v0 - 1.0 +
                0.5 * (q.uc * q.uc + q.us * q.us + q.vc * q.vc + q.vs * q.vs);
    double hc = 2.0 * (q.u0 * q.uc + q.v0 * q.vc), hs = 2.0 * (q.u0 * q.us + q.v0 * q.vs);
    double hc2 = 0.5 * (q.uc * q.uc - q.us * q.us + q.vc * q.vc - q.vs * q.vs);
    double hs2 = q.uc * q.us + q.vc * q.vs;
    double t[4], at[4][5], found[4][3], key[4];
    int ok[4], order[4];
    quartic_candidates(h0, hc, hs, hc2, hs2, t);
    quartic_polish(residual, &q, t, at, ok);
    for (int k = 0; k < 4; k++) {
        double size = hypot(at[k][3], at[k][4]);
        found[k][0] = ok[k] ? t[k] : NAN;
        found[k][1] = ok[k] ? at[k][4] / size : NAN;
        found[k][2] = ok[k] ? at[k][3] / size : NAN;
        key[k] = wrap(found[k][0] - P->off[0]);
    }
    quartic_order(key, order);
    for (int k = 0; k < 4; k++)
        for (int i = 0; i < 3; i++) slots[k][i] = found[order[k]][i];
}

/* The general case's two rows (elbow up, down) of a slot (ThreeParallelBatch._arm_batch). */
static void arm_rows(const Params *P, const double w[3], const double *r, const double slot[3],
                     double free, double rows[2][JOINTS])
{
    const double s1 = P->k[0], c1 = P->k[1], s4 = P->k[2], c4 = P->k[3];
    const double a1 = P->len[0], d1 = P->len[1], a2 = P->len[2];
    const double a3 = P->len[3], a4 = P->len[5], d5 = P->len[6], a5 = P->len[7];
    const double *o = P->off;
    double t1 = slot[0], cos5 = slot[1], st5 = slot[2];
    double ct = cos(t1), st = sin(t1);
    double y1[3] = {-c1 * st, c1 * ct, s1}, z1[3] = {s1 * st, -s1 * ct, c1};
    double x6 = r[0] * z1[0] + r[3] * z1[1] + r[6] * z1[2];
    double y6 = r[1] * z1[0] + r[4] * z1[1] + r[7] * z1[2];
    double t5 = atan2(st5, cos5), t6 = wrist_t6(P, x6, y6, hypot(x6, y6), cos5, st5, free);
    double phi = arm_phi(P, r, ct, st, y1, cos5, st5, t6), cp = cos(phi), sp = sin(phi);
    double qx = w[0] - a1 * ct, qy = w[1] - a1 * st, qz = w[2] - d1;
    double ex = a4 + a5 * cos5, ey = c4 * a5 * st5 - s4 * d5;
    double bx = ct * qx + st * qy - (cp * ex - sp * ey);
    double by = y1[0] * qx + y1[1] * qy + y1[2] * qz - (sp * ex + cp * ey);
    double cos3 = (bx * bx + by * by - (a2 * a2 + a3 * a3)) / (2.0 * a2 * a3);
    if (!clamp_cos(&cos3)) cos3 = NAN;
    double sin3 = sqrt(1.0 - cos3 * cos3), heading = atan2(by, bx);
    for (int elbow = 0; elbow < 2; elbow++) {
        double st3 = elbow == 0 ? sin3 : -sin3;
        double t3 = atan2(st3, cos3);
        double t2 = heading - atan2(a3 * st3, a2 + a3 * cos3);
        double t4 = phi - t2 - t3;
        double *row = rows[elbow];
        double q[JOINTS] = {t1 - o[0], t2 - o[1], t3 - o[2], t4 - o[3], t5 - o[4], t6 - o[5]};
        int bad = 0;
        for (int j = 0; j < JOINTS; j++) bad |= isnan(row[j] = wrap(q[j]));
        if (bad)
            for (int j = 0; j < JOINTS; j++) row[j] = NAN;
    }
}

static void solve_one(const Params *P, const double *p, const double *r, double free,
                      double out[BRANCHES][JOINTS])
{
    if (P->family[0] == 0.0) {
        intersecting_rows(P, p, r, free, out);
        return;
    }
    const double d6 = P->len[8];
    const double n[3] = {r[2], r[5], r[8]};
    const double w[3] = {p[0] - d6 * n[0], p[1] - d6 * n[1], p[2] - d6 * n[2]};
    double slots[4][3];
    general_slots(P, w, n, slots);
    for (int k = 0; k < 4; k++) arm_rows(P, w, r, slots[k], free, &out[2 * k]);
}

#include "_six_r_module.h"

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_three_parallel",
    "Compiled twin of kin.ik.analytic.six_r.three_parallel, both its cases (optional speed-up).",
    -1, methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__three_parallel(void)
{
    PyObject *m = six_r_module(&module);
    if (m != NULL && PyModule_AddFunctions(m, quartic_methods) < 0) Py_CLEAR(m);
    return m;
}

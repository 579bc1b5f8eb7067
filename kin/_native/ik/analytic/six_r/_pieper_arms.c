/*
 * Compiled twin of the Pieper family (kin/ik/analytic/six_r/pieper.py and its NumPy algorithm
 * pieper_batch.py, pieper_quartic.py), all four of its cases: a spherical wrist after axes 1-2
 * meeting (intersecting), parallel (parallel), skew (general), or axes 2-3 parallel (parallel23:
 * PUMA 560, Kinova Jaco 2; SphericalWrist6R, "spherical_wrist"). The 8 branches of a target, the
 * same steps as the NumPy form's (_arms_batch, _general_t3_batch, _wrist_batch) in the same order,
 * the general case's quartic by _trig_quartic.h, the wrist's flips by _wrist_flips.h; with verify
 * (each branch moved into the limits and measured by the table's DH product, _six_r_twin.h). The
 * NumPy form is the reference and the fallback when this extension is not built;
 * tests/native/test_six_r_twins.py (the parallel23 case) and tests/native/test_six_r_family_twins.py (the three
 * others) compare the two. Angles in radians, lengths in meters.
 */
#include "_six_r_twin.h"
#include "_wrist_flips.h"

#include "_trig_quartic.h"

/* The parameter layout (Pieper6R.c_fields fills it by name from LAYOUT). X(field, size, doc) */
#define PIEPER_ARMS_PARAMS(X)                                                                   \
    FRAME_PARAMS(X)                                                                             \
    X(family, 1, "0: intersecting (a1 = 0), 1: parallel (sin alpha1 = 0), 2: general, 3: parallel23") \
    X(k, 3, "Pieper6R._k: sin, cos of alpha1, |g|^2's constant g0 [m^2]")                      \
    X(e, 9, "Pieper6R._e (the case's constants), zeros after its own")                          \
    X(g, 9, "Pieper6R._g: g1, g2, g3 as (constant, cos t3, sin t3) [m]")                        \
    X(wrist, 10, "Pieper6R._wrist: sin, cos of alpha1 .. alpha5")                               \
    X(classic, 1, "1 when both wrist twists are +-90 deg")                                      \
    X(len, 3, "a1, d1, d6 [m]")                                                                 \
    X(off, 6, "theta offsets [rad]")

TWIN_PARAMS(PIEPER_ARMS_PARAMS)

/* x where x < 0 is within COS_SLACK (scale + 1) of 0 -> 0 (pieper_batch's np.where). */
static inline double floor_slack(double x, double scale)
{
    return (x < 0.0 && x >= -COS_SLACK * (scale + 1.0)) ? 0.0 : x;
}

/* The arm slot `slot` (t1, t2, t3) [rad] -> its two rows (wrist no flip, flip). */
static void wrist_rows(const Params *P, const double *r, const double t[3], double free,
                       double rows[2][JOINTS])
{
    const double *W = P->wrist, *o = P->off;
    const double s4 = W[6], c4 = W[7], s5 = W[8], c5 = W[9];
    double vx = r[0], vy = r[3], vz = r[6], nx = r[2], ny = r[5], nz = r[8];
    for (int i = 0; i < 3; i++) {
        double ct = cos(t[i]), st = sin(t[i]), sa = W[2 * i], ca = W[2 * i + 1];
        double x = ct * vx + st * vy, y = -st * vx + ct * vy;
        vx = x;
        vy = ca * y + sa * vz;
        vz = -sa * y + ca * vz;
        x = ct * nx + st * ny, y = -st * nx + ct * ny;
        nx = x;
        ny = ca * y + sa * nz;
        nz = -sa * y + ca * nz;
    }
    double cos5 = (c4 * c5 - nz) / (s4 * s5), sin5;
    if (P->classic[0] != 0.0) {
        sin5 = sqrt(nx * nx + ny * ny);
    } else {
        if (!clamp_cos(&cos5)) cos5 = NAN;
        sin5 = sqrt(fmax(0.0, 1.0 - cos5 * cos5));
    }
    double angles[2][3];
    wrist_flips(atan2(ny, nx), cos5, sin5, s4, c4, s5, c5, vx, vy, vz, free + o[3], angles);
    wrist_rows_fill(wrap(t[0] - o[0]), wrap(t[1] - o[1]), wrap(t[2] - o[2]), angles, o, rows);
}

/* A general-family target: rt = R - a1^2 [m^2], z = Wz - d1 [m] (pieper_quartic.py). */
typedef struct {
    const Params *P;
    double rt, z;
} Target;

/* PieperQuartic._residual: E(t3), dE/dt3, the bound on |E| of a root [m^2]. */
static void residual(const void *ctx, double t3, double out[5])
{
    const Target *T = ctx;
    const double *G = T->P->g, sa1 = T->P->k[0], ca1 = T->P->k[1], a1 = T->P->len[0];
    double rt = T->rt, z = T->z, c3 = cos(t3), s3 = sin(t3);
    double g1 = G[0] + G[1] * c3 + G[2] * s3, g2 = G[3] + G[4] * c3 + G[5] * s3;
    double g3 = G[6] + G[7] * c3 + G[8] * s3;
    double p_sq = g1 * g1 + g2 * g2, g_sq = p_sq + g3 * g3;
    double u = (rt - g_sq) / (2.0 * a1), w = (z - ca1 * g3) / sa1;
    double d1 = G[2] * c3 - G[1] * s3, d2 = G[5] * c3 - G[4] * s3, d3 = G[8] * c3 - G[7] * s3;
    double dp = 2.0 * (g1 * d1 + g2 * d2);
    double du = -(dp + 2.0 * g3 * d3) / (2.0 * a1), dw = -ca1 * d3 / sa1;
    double rounding = fabs(u) * (fabs(rt) + g_sq) / fabs(a1) + fabs(w) * (fabs(z) + fabs(g3)) / fabs(sa1);
    out[0] = u * u + w * w - p_sq;
    out[1] = 2.0 * (u * du + w * dw) - dp;
    out[2] = 2.0 * 1e-10 * sqrt(p_sq) + 16.0 * QUARTIC_EPS * (rounding + p_sq); /* REACH_TOL */
    out[3] = out[4] = 0.0;
}

/* The general family's roots t3[4] (_general_t3_batch): ascending q3, then NaN. */
static void general_t3(const Params *P, double rt, double z, double t3[4])
{
    const double *E = P->e, *G = P->g, sa1 = P->k[0], ca1 = P->k[1], g0 = P->k[2];
    double u0 = (rt - g0) / (2.0 * P->len[0]), w0 = (z - ca1 * G[6]) / sa1;
    double h0 = u0 * u0 + w0 * w0 + E[4];
    double hc = 2.0 * (u0 * E[0] + w0 * E[2]) - E[5], hs = 2.0 * (u0 * E[1] + w0 * E[3]) - E[6];
    double t[4], at[4][5], key[4];
    int ok[4], order[4];
    Target target = {P, rt, z};
    quartic_candidates(h0, hc, hs, E[7], E[8], t);
    quartic_polish(residual, &target, t, at, ok);
    for (int k = 0; k < 4; k++) {
        if (!ok[k]) t[k] = NAN;
        key[k] = wrap(t[k] - P->off[2]);
    }
    quartic_order(key, order);
    for (int k = 0; k < 4; k++) t3[k] = t[order[k]];
}

/* The parallel23 case (_parallel23_arms, then _wrist_batch): the wrist centre's height gives y1, the
   base radius the shoulder, the law of cosines in the plane of axes 2-3 the elbow; rows 4
   shoulder + 2 elbow + flip. */
static void parallel23_rows(const Params *P, const double *p, const double *r, double free,
                            double out[BRANCHES][JOINTS])
{
    const double *W = P->wrist, *E = P->e;
    const double s1 = W[0], c1 = W[1], sa3 = W[4], ca3 = W[5], s4 = W[6], c4 = W[7];
    const double s5 = W[8], c5 = W[9], lx = E[0], ly = E[1], l3 = E[2], phi3 = E[3], h = E[4];
    const int classic = P->classic[0] != 0.0;
    const double a1 = P->len[0], d1 = P->len[1], a2 = P->g[0], d6 = P->len[2];
    const double *o = P->off;
    for (int b = 0; b < BRANCHES; b++)
        for (int j = 0; j < JOINTS; j++) out[b][j] = NAN;
    /* 1. wrist centre, 2. joint 1 */
    double wx = p[0] - d6 * r[2], wy = p[1] - d6 * r[5], wz = p[2] - d6 * r[8];
    double y1 = (wz - d1 - c1 * h) / s1;
    double b = c1 * y1 - s1 * h;
    double rho2 = wx * wx + wy * wy;
    double a_sq = rho2 - b * b;
    if (a_sq < 0.0) {
        if (a_sq < -COS_SLACK * (rho2 + b * b + 1.0)) return;
        a_sq = 0.0;
    }
    double radius = sqrt(a_sq), heading = atan2(wy, wx);
    const double u0[3] = {r[0], r[3], r[6]}, n0[3] = {r[2], r[5], r[8]};
    double two_a2_l3 = 2.0 * a2 * l3, base_sq = a2 * a2 + l3 * l3;
    for (int shoulder = 0; shoulder < 2; shoulder++) {
        double big_a = shoulder == 0 ? radius : -radius;
        double t1 = heading - atan2(b, big_a);
        double x1 = big_a - a1;
        /* 3. elbow */
        double cos3 = (x1 * x1 + y1 * y1 - base_sq) / two_a2_l3;
        if (!clamp_cos(&cos3)) continue;
        double delta = acos(cos3), ct1 = cos(t1), st1 = sin(t1);
        double ux = ct1 * u0[0] + st1 * u0[1], uy = -st1 * u0[0] + ct1 * u0[1];
        double uz = -s1 * uy + c1 * u0[2];
        uy = c1 * uy + s1 * u0[2];
        double nx = ct1 * n0[0] + st1 * n0[1], ny = -st1 * n0[0] + ct1 * n0[1];
        double nz = -s1 * ny + c1 * n0[2];
        ny = c1 * ny + s1 * n0[2];
        double heading1 = atan2(y1, x1);
        for (int elbow = 0; elbow < 2; elbow++) {
            double t3 = elbow == 0 ? -phi3 - delta : -phi3 + delta;
            double ct3 = cos(t3), st3 = sin(t3);
            double t2 = heading1 - atan2(lx * st3 + ly * ct3, a2 + lx * ct3 - ly * st3);
            double t23 = t2 + t3, c23 = cos(t23), s23 = sin(t23);
            double vx = c23 * ux + s23 * uy, vy = -s23 * ux + c23 * uy;
            double wvx = c23 * nx + s23 * ny, wvy = -s23 * nx + c23 * ny;
            double vz = -sa3 * vy + ca3 * uz;
            vy = ca3 * vy + sa3 * uz;
            double mz = -sa3 * wvy + ca3 * nz;
            wvy = ca3 * wvy + sa3 * nz;
            /* 4. wrist */
            double cos5 = (c4 * c5 - mz) / (s4 * s5), sin5;
            if (classic) {
                sin5 = hypot(wvx, wvy);
            } else {
                if (!clamp_cos(&cos5)) continue;
                sin5 = sqrt(fmax(0.0, 1.0 - cos5 * cos5));
            }
            double angles[2][3];
            wrist_flips(atan2(wvy, wvx), cos5, sin5, s4, c4, s5, c5, vx, vy, vz, free + o[3],
                        angles);
            wrist_rows_fill(wrap(t1 - o[0]), wrap(t2 - o[1]), wrap(t3 - o[2]), angles, o,
                            &out[4 * shoulder + 2 * elbow]);
        }
    }
}

static void solve_one(const Params *P, const double *p, const double *r, double free,
                      double out[BRANCHES][JOINTS])
{
    if (P->family[0] == 3.0) {
        parallel23_rows(P, p, r, free, out);
        return;
    }
    const double *K = P->k, *G = P->g;
    const double sa1 = K[0], ca1 = K[1], g0 = K[2], size = P->e[0], psi = P->e[1];
    const double a1 = P->len[0], d1 = P->len[1], d6 = P->len[2];
    const int family = (int)P->family[0];
    double wx = p[0] - d6 * r[2], wy = p[1] - d6 * r[5], wz = p[2] - d6 * r[8];
    double z = wz - d1, rho2 = wx * wx + wy * wy, big_r = rho2 + z * z;
    double heading = atan2(wy, wx);
    if (family == 2) {
        double t3s[4];
        general_t3(P, big_r - a1 * a1, z, t3s);
        for (int arm = 0; arm < 4; arm++) {
            double t3 = t3s[arm], c3 = cos(t3), s3 = sin(t3);
            double g1 = G[0] + G[1] * c3 + G[2] * s3, g2 = G[3] + G[4] * c3 + G[5] * s3;
            double g3 = G[6] + G[7] * c3 + G[8] * s3;
            double u = (big_r - a1 * a1 - (g1 * g1 + g2 * g2 + g3 * g3)) / (2.0 * a1);
            double w = (z - ca1 * g3) / sa1;
            double t2 = atan2(g1 * w - g2 * u, g1 * u + g2 * w), c2 = cos(t2), s2 = sin(t2);
            double h1 = c2 * g1 - s2 * g2, h2 = s2 * g1 + c2 * g2;
            double t[3] = {heading - atan2(ca1 * h2 - sa1 * g3, a1 + h1), t2, t3};
            wrist_rows(P, r, t, free, &out[2 * arm]);
        }
        return;
    }
    const int parallel = family == 1;
    double cos3 = parallel ? (ca1 * z - G[6]) / size : (big_r - g0) / size;
    double delta = clamp_cos(&cos3) ? acos(cos3) : NAN;
    double sign = copysign(1.0, a1 * ca1);
    for (int elbow = 0; elbow < 2; elbow++) {
        double t3 = elbow == 0 ? psi - delta : psi + delta;
        double c3 = cos(t3), s3 = sin(t3);
        double g1 = G[0] + G[1] * c3 + G[2] * s3;
        double g2 = G[3] + G[4] * c3 + G[5] * s3;
        double g3 = G[6] + G[7] * c3 + G[8] * s3;
        double h1s[2], h2s[2];
        if (parallel) {
            double h1 = (big_r - a1 * a1 - (g1 * g1 + g2 * g2 + g3 * g3)) / (2.0 * a1);
            double p_sq = g1 * g1 + g2 * g2;
            double h2 = sign * sqrt(floor_slack(p_sq - h1 * h1, p_sq + h1 * h1));
            h1s[0] = h1s[1] = h1;
            h2s[0] = h2;
            h2s[1] = -h2;
        } else {
            double h2 = (z - ca1 * g3) / sa1;
            double b = ca1 * h2 - sa1 * g3;
            double radius = sqrt(floor_slack(rho2 - b * b, rho2 + b * b));
            h1s[0] = radius - a1;
            h1s[1] = -radius - a1;
            h2s[0] = h2s[1] = h2;
        }
        double base = atan2(g2, g1);
        for (int side = 0; side < 2; side++) {
            double h1 = h1s[side], h2 = h2s[side];
            double t[3] = {heading - atan2(ca1 * h2 - sa1 * g3, a1 + h1), atan2(h2, h1) - base,
                           t3};
            wrist_rows(P, r, t, free, &out[2 * (2 * side + elbow)]);
        }
    }
}

#include "_six_r_module.h"

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_pieper_arms",
    "Compiled twin of kin.ik.analytic.six_r.pieper, all four of its cases (optional speed-up).",
    -1, methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__pieper_arms(void)
{
    PyObject *m = six_r_module(&module);
    if (m != NULL && PyModule_AddFunctions(m, quartic_methods) < 0) Py_CLEAR(m);
    return m;
}

/*
 * Compiled twin of the Pieper family (kin/ik/analytic/six_r/pieper.py and its NumPy algorithm
 * pieper_batch.py) for its parallel23 case, a spherical wrist and parallel axes 2-3: PUMA 560,
 * Kinova Jaco 2 (SphericalWrist6R, "spherical_wrist"). The 8 branches of a target, for speed; with
 * verify (each branch moved into the limits and measured by the table's DH product,
 * _six_r_twin.h). The NumPy form is the reference and the fallback when this extension is not
 * built; tests/test_six_r_twins.py compares the two. Angles in radians, lengths in meters.
 */
#include "_six_r_twin.h"
#include "_wrist_flips.h"

/* The parameter layout (SphericalWrist6R.c_fields fills it by name from LAYOUT).
   X(field, size, doc) */
#define SPHERICAL_PARAMS(X)                                                                     \
    FRAME_PARAMS(X)                                                                             \
    X(k, 12, "SphericalWrist6R._k: sin, cos of alpha1, 3, 4, 5; forearm lx, ly, |l| [m], angle") \
    X(classic, 1, "1 when both wrist twists are +-90 deg")                                      \
    X(len, 5, "a1, d1, a2, lateral h, d6 [m]")                                                  \
    X(off, 6, "theta offsets [rad]")

TWIN_PARAMS(SPHERICAL_PARAMS)

static void solve_one(const Params *P, const double *p, const double *r, double free,
                      double out[BRANCHES][JOINTS])
{
    const double *K = P->k;
    const double s1 = K[0], c1 = K[1], sa3 = K[2], ca3 = K[3], s4 = K[4], c4 = K[5];
    const double s5 = K[6], c5 = K[7], lx = K[8], ly = K[9], l3 = K[10], phi3 = K[11];
    const int classic = P->classic[0] != 0.0;
    const double a1 = P->len[0], d1 = P->len[1], a2 = P->len[2], h = P->len[3], d6 = P->len[4];
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
        if (cos3 > 1.0 || cos3 < -1.0) {
            if (fabs(cos3) > 1.0 + COS_SLACK) continue;
            cos3 = cos3 > 0.0 ? 1.0 : -1.0;
        }
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
                if (cos5 > 1.0 || cos5 < -1.0) {
                    if (fabs(cos5) > 1.0 + COS_SLACK) continue;
                    cos5 = cos5 > 0.0 ? 1.0 : -1.0;
                }
                sin5 = sqrt(fmax(0.0, 1.0 - cos5 * cos5));
            }
            double q1 = wrap(t1 - o[0]), q2 = wrap(t2 - o[1]), q3 = wrap(t3 - o[2]);
            int index = 4 * shoulder + 2 * elbow;
            double angles[2][3];
            wrist_flips(atan2(wvy, wvx), cos5, sin5, s4, c4, s5, c5, vx, vy, vz, free + o[3],
                        angles);
            for (int flip = 0; flip < 2; flip++) {
                double *row = out[index + flip];
                row[0] = q1;
                row[1] = q2;
                row[2] = q3;
                row[3] = wrap(angles[flip][0] - o[3]);
                row[4] = wrap(angles[flip][1] - o[4]);
                row[5] = wrap(angles[flip][2] - o[5]);
            }
        }
    }
}

#include "_six_r_module.h"

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_spherical_wrist",
    "Compiled twin of kin.ik.analytic.spherical_wrist (optional speed-up).", -1, methods, NULL,
    NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__spherical_wrist(void) { return six_r_module(&module); }

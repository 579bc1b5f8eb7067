/*
 * Compiled twin of the three-parallel family (kin/ik/analytic/six_r/three_parallel.py and its
 * NumPy algorithm three_parallel_batch.py) for its intersecting case, axes 5 and 6 meeting: the UR
 * arms (URWrist6R, "ur_wrist"). The 8 branches of a target, for speed; with verify (each branch
 * moved into the limits and measured by the table's DH product, _six_r_twin.h). The NumPy form is
 * the reference and the fallback when this extension is not built; tests/test_six_r_twins.py
 * compares the two. Angles in radians, lengths in meters.
 */
#include "_six_r_twin.h"

/* The parameter layout (URWrist6R.c_fields fills it by name from LAYOUT). X(field, size, doc) */
#define UR_PARAMS(X)                                                            \
    FRAME_PARAMS(X)                                                             \
    X(k, 8, "URWrist6R._k: sin, cos alpha1; ex, ey [m]; sin, cos alpha4, alpha5") \
    X(classic, 1, "1 when both wrist twists are +-90 deg")                        \
    X(len, 6, "a1, d1, a2, a3, lateral h, d6 [m]")                                \
    X(off, 6, "theta offsets [rad]")

TWIN_PARAMS(UR_PARAMS)

static void solve_one(const Params *P, const double *p, const double *r, double free,
                      double out[BRANCHES][JOINTS])
{
    const double s1 = P->k[0], c1 = P->k[1], ex = P->k[2], ey = P->k[3];
    const double s4 = P->k[4], c4 = P->k[5], s5a = P->k[6], c5a = P->k[7];
    const int classic = P->classic[0] != 0.0;
    const double a1 = P->len[0], d1 = P->len[1], a2 = P->len[2], a3 = P->len[3];
    const double h = P->len[4], d6 = P->len[5];
    const double *o = P->off;
    for (int b = 0; b < BRANCHES; b++)
        for (int j = 0; j < JOINTS; j++) out[b][j] = NAN;
    const double r00 = r[0], r01 = r[1], r02 = r[2], r10 = r[3], r11 = r[4], r12 = r[5];
    const double r20 = r[6], r21 = r[7], r22 = r[8];
    /* 1. joint 1 from p5 */
    double px = p[0] - d6 * r02, py = p[1] - d6 * r12, pz = p[2] - d6 * r22;
    double rho = hypot(px, py);
    if (rho == 0.0) return;
    double k = (c1 * (pz - d1) - h) / (s1 * rho);
    if (k > 1.0 || k < -1.0) {
        if (fabs(k) > 1.0 + COS_SLACK) return;
        k = k > 0.0 ? 1.0 : -1.0;
    }
    double beta = atan2(py, px), asin_k = asin(k);
    double two_a2a3 = 2.0 * a2 * a3, base_sq = a2 * a2 + a3 * a3;
    for (int shoulder = 0; shoulder < 2; shoulder++) {
        double t1 = shoulder == 0 ? beta - asin_k : beta - M_PI + asin_k;
        double ct = cos(t1), st = sin(t1);
        double y1[3] = {-c1 * st, c1 * ct, s1}, z1[3] = {s1 * st, -s1 * ct, c1};
        /* 2. z1 in frame 6 */
        double x6 = r00 * z1[0] + r10 * z1[1] + r20 * z1[2];
        double y6 = r01 * z1[0] + r11 * z1[1] + r21 * z1[2];
        double w = r02 * z1[0] + r12 * z1[1] + r22 * z1[2];
        double cos5 = (c4 * c5a - w) / (s4 * s5a), xy6 = hypot(x6, y6), sin5;
        if (classic) {
            sin5 = xy6;
        } else {
            if (cos5 > 1.0 || cos5 < -1.0) {
                if (fabs(cos5) > 1.0 + COS_SLACK) continue;
                cos5 = cos5 > 0.0 ? 1.0 : -1.0;
            }
            sin5 = sqrt(1.0 - cos5 * cos5);
        }
        double qx = px - a1 * ct, qy = py - a1 * st, qz = pz - d1;
        double ax = ct * qx + st * qy;
        double ay = y1[0] * qx + y1[1] * qy + y1[2] * qz;
        for (int wrist = 0; wrist < 2; wrist++) {
            double st5 = wrist == 0 ? sin5 : -sin5;
            double t5 = atan2(st5, cos5), t6;
            if (xy6 <= 1e-12) { /* _six_r.SINGULAR */
                t6 = free + o[5];
            } else { /* (x6, y6) = Rz(-t6) (vx, vy) */
                double vx = s4 * st5, vy = c5a * s4 * cos5 + s5a * c4;
                t6 = atan2(vy, vx) - atan2(y6, x6);
            }
            /* 3. phi */
            double ct6 = cos(t6), st6 = sin(t6);
            double xi0 = cos5 * ct6 - st5 * c5a * st6;
            double xi1 = -cos5 * st6 - st5 * c5a * ct6;
            double xi2 = s5a * st5;
            double rx = r00 * xi0 + r01 * xi1 + r02 * xi2;
            double ry = r10 * xi0 + r11 * xi1 + r12 * xi2;
            double rz = r20 * xi0 + r21 * xi1 + r22 * xi2;
            double cphi = ct * rx + st * ry;
            double sphi = y1[0] * rx + y1[1] * ry + y1[2] * rz;
            double phi = atan2(sphi, cphi), cp = cos(phi), sp = sin(phi);
            double bx = ax - (cp * ex - sp * ey), by = ay - (sp * ex + cp * ey);
            double cos3 = (bx * bx + by * by - base_sq) / two_a2a3;
            if (cos3 > 1.0 || cos3 < -1.0) {
                if (fabs(cos3) > 1.0 + COS_SLACK) continue;
                cos3 = cos3 > 0.0 ? 1.0 : -1.0;
            }
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

#include "_six_r_module.h"

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_ur_wrist",
    "Compiled twin of kin.ik.analytic.ur_wrist (optional speed-up).", -1, methods, NULL, NULL,
    NULL, NULL};

PyMODINIT_FUNC PyInit__ur_wrist(void) { return six_r_module(&module); }

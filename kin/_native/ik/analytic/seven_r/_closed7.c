/*
 * Compiled twin of kin/ik/analytic/seven_r/seven_dof.py (SevenDofIK.pose / SevenDofIK.position and the choice of the
 * branch nearest a start): the same arithmetic, operation for operation, for speed, except that
 * the angle pairs a limit check drops are dropped before their second angle is computed
 * (rotation_pair_fit in _twin.h), and a scan skips the joint-1 values where the elbow has no
 * root (elbow_window) or where no branch, followed as directions, fits the limits (q1_may_fit):
 * skips that never drop a branch the Python module keeps. The Python module is the reference
 * and the fallback when this extension is not built; the tests compare the two. Angles in
 * radians, lengths in meters.
 *
 * first(params, mode, target, starts, out, step) -> int
 *   params: float64[PARAM_COUNT], SevenDofIK.c_params (CLOSED7_PARAMS below, exported as LAYOUT);
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
#include "_twin.h"

/*
 * The parameter layout, declared here once. SevenDofIK.c_params reads the order, offsets and
 * sizes from LAYOUT (exported below), filling each field by name; a test checks both sides.
 * X(field, size, description)
 */
#define CLOSED7_PARAMS(X)                                            \
    X(off, 7, "theta offsets [rad]")                                 \
    X(sin, 7, "sin alpha")                                           \
    X(cos, 7, "cos alpha")                                           \
    X(a, 7, "a [m]")                                                 \
    X(d, 7, "d [m]")                                                 \
    X(lo, 7, "lower joint limits [rad]")                             \
    X(hi, 7, "upper joint limits [rad]")                             \
    X(s3, 3, "shoulder point in frame 3 [m]")                        \
    X(s3_2, 1, "its squared norm [m^2]")                             \
    X(wu, 3, "elbow vector u of the wrist centre [m]")               \
    X(g, 3, "Rx(alpha6) e_z")                                        \
    X(tool, 3, "tool origin in frame 7 [m]")                         \
    X(w7, 3, "wrist centre in frame 7 [m]")                          \
    X(ax7, 3, "(0, sin alpha7, cos alpha7)")                          \
    X(edge4, 5, "cos, sin of t4 at joint 4's lower, upper limit; 1 if they span a turn")  \
    X(arc, 24, "joints 2-7: cos, sin of t at the limits' middle, cos of half their span; 1 if wide")

TWIN_PARAMS(CLOSED7_PARAMS)

/* One arm branch: its joint values, angles t = q + offset and the cosines and sines of the
   angles that arm() computed anyway (the same values pose() would compute again). */
typedef struct {
    double t1, q2, q3, q4, t2, t3, t4, c1, s1, c3, s3, c4, s4;
} Arm;

static int inside(const Params *P, int i, double q)
{
    return P->lo[i] <= q && q <= P->hi[i];
}

/*
 * A test before arm()'s angles (not in the Python module: the same answers). Most joint-1 values
 * a scan visits inside the elbow window (below) give no branch: joint 3 or 4 lands outside its
 * limits, or (for a pose) joint 5 or 7. q1_may_fit() follows the branches as directions (cos,
 * sin: square roots and products instead of atan2, acos, sin and cos) and the joint ranges as
 * arcs, and says 0 only when every branch has a joint outside its arc, widened by a slack.
 * Where a direction could not be trusted to well within that slack (the roots of an equation
 * near each other, an equation too weak, a vector too short to normalise: the guards in
 * _twin.h), it says 1: the exact path decides. Worst cases under these guards: joints 3 and 4
 * off by 5e-10 rad, joint 2 by 2e-8, joints 5-7 by 3e-5 / rho6 rad (rho6 = |sin alpha5| |g_xy|,
 * 1 for humanoid7; the wrist is not tested below CHAIN_RHO_MIN); errors of 1e-12 are usual.
 * Hence ARC_SLACK and CHAIN_SLACK. A branch arm() and pose() would keep is never skipped; the
 * tests compare the twin with the Python module at the limits' edges.
 */
/* joint j's arc (j = 1..6: joints 2-7) */
#define ARC(j) (P->arc + 4 * ((j) - 1))

/* x <- (Rz(t) Rx(alpha))^T x for the direction (ct, st) of t and sa, ca of alpha. */
static inline void turn_back(double ct, double st, double sa, double ca, double *x)
{
    double a = ct * x[0] + st * x[1], b = ct * x[1] - st * x[0];
    x[0] = a;
    x[1] = ca * b + sa * x[2];
    x[2] = ca * x[2] - sa * b;
}

/* Whether some wrist of the arm directions (joints 1-4: c[i], s[i]) may fit joints 5-7 for the
   pose's X7, Z7 (as pose() solves it). */
static int wrist_may_fit(const Params *P, const double *c, const double *s, const double *X7,
                         const double *Z7)
{
    const double *S = P->sin, *C = P->cos, *g = P->g;
    if (!(fabs(S[4]) * sqrt(g[0] * g[0] + g[1] * g[1]) >= CHAIN_RHO_MIN)) return 1; /* joint 6's */
    double x[3] = {X7[0], X7[1], X7[2]}, z[3] = {Z7[0], Z7[1], Z7[2]};
    for (int i = 0; i < 4; i++) {
        turn_back(c[i], s[i], S[i], C[i], x);
        turn_back(c[i], s[i], S[i], C[i], z);
    }
    double c6s[2], s6s[2];
    int n6 = root_directions(S[4] * g[1], S[4] * g[0], z[2] - C[4] * g[2], c6s, s6s);
    if (n6 < 0) return 1;
    for (int k = 0; k < n6; k++) {
        double c6 = c6s[k], s6 = s6s[k], c5, s5, c7, s7;
        if (!arc_admits(ARC(5), c6, s6, CHAIN_SLACK)) continue;
        double mx = g[0] * c6 - g[1] * s6, my = C[4] * (g[0] * s6 + g[1] * c6) - S[4] * g[2];
        if (!angle_difference(z[0], z[1], SHORT_UNIT, mx, my, SHORT_UNIT, &c5, &s5)) return 1;
        if (!arc_admits(ARC(4), c5, s5, CHAIN_SLACK)) continue;
        double n[3] = {x[0], x[1], x[2]};
        turn_back(c5, s5, S[4], C[4], n);
        double nx = c6 * n[0] + s6 * n[1], ny = C[5] * (c6 * n[1] - s6 * n[0]) + S[5] * n[2];
        if (!angle_difference(nx, ny, SHORT_UNIT, 1.0, 0.0, 0.0, &c7, &s7)) return 1;
        if (arc_admits(ARC(6), c7, s7, CHAIN_SLACK)) return 1;
    }
    return 0;
}

/* 0 when arm() (and, with X7 and Z7 of a pose, pose()) surely finds no branch at the joint-1
   direction (c1, s1), for the point d seen from the shoulder (as arm() computes it) and the
   elbow equation pe cos t4 + qe sin t4 = ke; else 1. */
static int q1_may_fit(const Params *P, double c1, double s1, const double *dv, double pe,
                      double qe, double ke, const double *u, const double *X7, const double *Z7)
{
    double c4s[2], s4s[2], c3s[2], s3s[2];
    int n4 = root_directions(pe, qe, ke, c4s, s4s);
    if (n4 < 0) return 1;
    const double *S = P->sin, *C = P->cos, *s3v = P->s3;
    for (int i = 0; i < n4; i++) {
        double c4 = c4s[i], s4 = s4s[i];
        if (!arc_admits(ARC(3), c4, s4, ARC_SLACK)) continue;
        double vy0 = u[0] * s4 + u[1] * c4 - s3v[1], vz0 = u[2] - s3v[2];
        double v0 = u[0] * c4 - u[1] * s4 - s3v[0];
        double v1 = C[2] * vy0 - S[2] * vz0, v2 = S[2] * vy0 + C[2] * vz0;
        int n3 = root_directions(S[1] * v1, S[1] * v0, dv[2] - C[1] * v2, c3s, s3s);
        if (n3 < 0) return 1;
        for (int j = 0; j < n3; j++) {
            double c3 = c3s[j], s3 = s3s[j];
            if (!arc_admits(ARC(2), c3, s3, ARC_SLACK)) continue;
            if (X7 == NULL) return 1; /* a position: joints 5-7 are the start's */
            /* t2 = atan2(d_y, d_x) - atan2(m_y, m_x) (rotation_pair) */
            double mx = v0 * c3 - v1 * s3, my = C[1] * (v0 * s3 + v1 * c3) - S[1] * v2, c2, s2;
            if (!angle_difference(dv[0], dv[1], SHORT_XY, mx, my, SHORT_XY, &c2, &s2)) return 1;
            if (!arc_admits(ARC(1), c2, s2, CHAIN_SLACK)) continue;
            double cs[4] = {c1, c2, c3, c4}, ss[4] = {s1, s2, s3, s4};
            if (wrist_may_fit(P, cs, ss, X7, Z7)) return 1;
        }
    }
    return 0;
}

/* subproblems.fold_distance of p cos t + q sin t = k, kept in *fold when less (fold: NULL, none). */
static inline void fold_min(double *fold, double p, double q, double k)
{
    if (fold == NULL) return;
    double rho = hypot(p, q), f = rho >= 1e-15 ? fabs(1.0 - fabs(k) / rho) : 0.0;
    if (f < *fold) *fold = f;
}

/* SevenDofIK._arm: branches putting Rz(t4) u (frame 3) on the point pt (frame 0); with fold, the
   least fold_distance of its equations (the elbow's, each elbow's shoulder equation), no skip. */
static int arm(const Params *P, double q1, const double *pt, const double *u, const double *X7,
               const double *Z7, Arm *out, double *fold)
{
    const double *S = P->sin, *C = P->cos, *off = P->off, *s3v = P->s3;
    double t1 = q1 + off[0];
    double c1 = cos(t1), s1 = sin(t1);
    double a1 = P->a[0];
    double x = pt[0] - a1 * c1, y = pt[1] - a1 * s1, z = pt[2] - P->d[0];
    double xr = c1 * x + s1 * y, yr = c1 * y - s1 * x;
    double dv[3] = {xr, C[0] * yr + S[0] * z, C[0] * z - S[0] * yr - P->d[1]};
    double dx = dv[0], dy = dv[1], dz = dv[2];
    double ux = u[0], uy = u[1], uz = u[2];
    double sx = s3v[0], sy = s3v[1], sz = s3v[2];
    double k = 0.5 * (ux * ux + uy * uy + uz * uz + P->s3_2[0] - dx * dx - dy * dy - dz * dz);
    double s3 = S[2], c3 = C[2], t4s[2];
    double pe = sx * ux + sy * uy, qe = sy * ux - sx * uy, ke = k - sz * uz;
    fold_min(fold, pe, qe, ke);
    if (fold == NULL && directions_on && !q1_may_fit(P, c1, s1, dv, pe, qe, ke, u, X7, Z7)) return 0;
    int n4 = harmonic_roots(pe, qe, ke, t4s), count = 0;
    for (int i = 0; i < n4; i++) {
        double t4 = t4s[i];
        double q4 = turn_remainder(t4 - off[3]);
        if (!inside(P, 3, q4)) continue;
        double c4 = cos(t4), s4 = sin(t4);
        double vy0 = ux * s4 + uy * c4 - sy, vz0 = uz - sz;
        double v[3] = {ux * c4 - uy * s4 - sx, c3 * vy0 - s3 * vz0, s3 * vy0 + c3 * vz0};
        double t2s[2], t3s[2], c3s[2], s3s[2];
        fold_min(fold, S[1] * v[1], S[1] * v[0], dv[2] - C[1] * v[2]);
        int n3 = rotation_pair_fit(S[1], C[1], v, dv, t2s, t3s, c3s, s3s, off[2], P->lo[2],
                                   P->hi[2]);
        for (int j = 0; j < n3; j++) {
            double t2 = t2s[j], t3 = t3s[j];
            double q3 = turn_remainder(t3 - off[2]);
            if (!inside(P, 2, q3)) continue;
            double q2 = turn_remainder(t2 - off[1]);
            if (!inside(P, 1, q2)) continue;
            Arm a = {t1, q2, q3, q4, t2, t3, t4, c1, s1, c3s[j], s3s[j], c4, s4};
            out[count++] = a;
        }
    }
    return count;
}

/*
 * Where joint 1 can be, given the elbow (a skip, not in the Python module: the same answers).
 * arm() finds a branch only when its elbow equation p cos t4 + q sin t4 = m has a root t4 inside
 * joint 4's limits, that is m in [m_low, m_high] (the range of the left side over those limits),
 * and m = c - (Bc cos t1 + Bs sin t1) / 2 depends on t1 = q1 + offset through a sinusoid:
 * |d|^2 = K0 + Bc cos t1 + Bs sin t1 (d the point seen from the shoulder, as arm() computes it).
 * So the t1 with a branch lie where cos(t1 - psi) is in [L, H] / R: |remainder(t1 - psi)| within
 * [inner, outer]. The window is widened (by 1e-9 m^2 in m, then 1e-9 rad) so that rounding never
 * skips a joint-1 value arm() would give a branch: a scan skips, without trigonometry, the values
 * (most of them) where the elbow cannot reach.
 */
typedef struct {
    int active;               /* 0: every t1 may have a branch (no skip) */
    double psi, inner, outer; /* [rad] */
} ElbowWindow;

static void elbow_window(const Params *P, const double *pt, const double *u, ElbowWindow *w)
{
    const double *S = P->sin, *C = P->cos, *e = P->edge4;
    double ux = u[0], uy = u[1], uz = u[2], sx = P->s3[0], sy = P->s3[1], sz = P->s3[2];
    double p = sx * ux + sy * uy, q = sy * ux - sx * uy, rho = hypot(p, q);
    /* m_low, m_high: p cos t4 + q sin t4 over joint 4's limits (the ends, and a peak inside) */
    double m_low = -rho, m_high = rho;
    if (e[4] == 0.0) {
        double at_low = p * e[0] + q * e[1], at_high = p * e[2] + q * e[3];
        m_low = at_low < at_high ? at_low : at_high;
        m_high = at_low < at_high ? at_high : at_low;
        double phi = atan2(q, p), low = atan2(e[1], e[0]), span = atan2(e[3], e[2]) - low;
        if (span < 0.0) span += TWO_PI;
        for (int k = 0; k < 2; k++) { /* the peak +rho at phi, -rho at phi + pi */
            double from_low = (k == 0 ? phi : phi + 0.5 * TWO_PI) - low;
            from_low -= TWO_PI * floor(from_low / TWO_PI);
            if (from_low <= span) {
                if (k == 0) m_high = rho;
                else m_low = -rho;
            }
        }
    }
    double x0 = pt[0], y0 = pt[1], z = pt[2] - P->d[0], a1 = P->a[0], d2 = P->d[1];
    double k0 = x0 * x0 + y0 * y0 + a1 * a1 + z * z + d2 * d2 - 2.0 * d2 * C[0] * z;
    double bc = -2.0 * a1 * x0 + 2.0 * d2 * S[0] * y0, bs = -2.0 * a1 * y0 - 2.0 * d2 * S[0] * x0;
    double c = 0.5 * (ux * ux + uy * uy + uz * uz + P->s3_2[0] - k0) - sz * uz;
    double r = hypot(bc, bs), slack = 1e-9 * (1.0 + fabs(c) + rho + r + k0);
    w->active = 0;
    if (!(r > 1e-9) || !isfinite(c)) return; /* t1 barely matters: no skip */
    double low = 2.0 * (c - m_high - slack) / r, high = 2.0 * (c - m_low + slack) / r;
    w->active = 1;
    w->psi = atan2(bs, bc);
    w->inner = high >= 1.0 ? 0.0 : (high <= -1.0 ? INFINITY : acos(high));
    w->outer = low <= -1.0 ? INFINITY : (low >= 1.0 ? -INFINITY : acos(low));
    w->inner -= 1e-9;
    w->outer += 1e-9;
}

/* Whether t1 [rad] is inside the window (or the window is off). */
static inline int elbow_admits(const ElbowWindow *w, double t1)
{
    if (!w->active) return 1;
    double delta = fabs(turn_remainder(t1 - w->psi));
    return w->inner <= delta && delta <= w->outer;
}

/* SevenDofIK.pose: joint vectors inside the limits (up to 8) for joint 1 at q1; with fold, the
   least fold_distance of its equations (arm's, then each arm's wrist equation). */
static int pose(const Params *P, double q1, const double *W, const double *X7, const double *Z7,
                double (*sol)[7], double *fold)
{
    Arm arms[4];
    int n = arm(P, q1, W, P->wu, X7, Z7, arms, fold), count = 0;
    const double *S = P->sin, *C = P->cos, *off = P->off, *g = P->g;
    for (int b = 0; b < n; b++) {
        const Arm *a = &arms[b];
        double xx = X7[0], xy = X7[1], xz = X7[2], zx = Z7[0], zy = Z7[1], zz = Z7[2];
        double cs[4] = {a->c1, cos(a->t2), a->c3, a->c4}, ss[4] = {a->s1, sin(a->t2), a->s3, a->s4};
        for (int i = 0; i < 4; i++) {
            double ct = cs[i], st = ss[i], sa = S[i], ca = C[i], tmp;
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
        /* Rz(t5) Rx(alpha5) Rz(t6) g = z4. */
        double s5 = S[4], c5 = C[4], s6 = S[5], c6 = C[5];
        double z4[3] = {zx, zy, zz}, t5s[2], t6s[2], c6s[2], s6s[2];
        fold_min(fold, s5 * g[1], s5 * g[0], z4[2] - c5 * g[2]);
        int n6 = rotation_pair_fit(s5, c5, g, z4, t5s, t6s, c6s, s6s, off[5], P->lo[5], P->hi[5]);
        for (int j = 0; j < n6; j++) {
            double t5 = t5s[j], t6 = t6s[j];
            double q5 = turn_remainder(t5 - off[4]);
            double q6 = turn_remainder(t6 - off[5]);
            if (!(inside(P, 4, q5) && inside(P, 5, q6))) continue;
            double ct = cos(t5), st = sin(t5), tmp;
            double nx = ct * xx + st * xy, ny = ct * xy - st * xx, nz;
            tmp = c5 * ny + s5 * xz;
            nz = c5 * xz - s5 * ny;
            ny = tmp;
            ct = c6s[j];
            st = s6s[j];
            tmp = ct * nx + st * ny;
            ny = ct * ny - st * nx;
            nx = tmp;
            ny = c6 * ny + s6 * nz;
            double q7 = turn_remainder(atan2(ny, nx) - off[6]);
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
static void elbow_vector(const Params *P, double q5, double q6, double q7, double *u)
{
    const double *S = P->sin, *C = P->cos, *off = P->off;
    double x = P->tool[0], y = P->tool[1], z = P->tool[2];
    double qs[3] = {q7, q6, q5};
    for (int k = 0; k < 3; k++) {
        int i = 6 - k;
        double t = qs[k] + off[i];
        double nx = P->a[i] + x, ny = C[i] * y - S[i] * z, nz = P->d[i] + S[i] * y + C[i] * z;
        double ct = cos(t), st = sin(t);
        x = ct * nx - st * ny;
        y = st * nx + ct * ny;
        z = nz;
    }
    u[0] = P->a[3] + x;
    u[1] = C[3] * y - S[3] * z;
    u[2] = P->d[3] + S[3] * y + C[3] * z;
}

/* SevenDofIK.pose_frame of a prepared pose T (frame-7 origin, R_0_7 row-major): the wrist centre W
   [m], the x axis X7 of frame 7 and the joint-7 axis Z7 of M, in frame 0. */
static void pose_frame(const Params *P, const double *T, double *W, double *X7, double *Z7)
{
    const double *R = T + 3, *w7 = P->w7, *ax = P->ax7;
    for (int i = 0; i < 3; i++) {
        const double *row = R + 3 * i;
        W[i] = T[i] + row[0] * w7[0] + row[1] * w7[1] + row[2] * w7[2];
        X7[i] = row[0];
        Z7[i] = row[1] * ax[1] + row[2] * ax[2];
    }
}

/* The first of the k starts Q (rows of 7) with a branch inside the limits for the target T (mode
   0: a pose, 12 values; 1: a position, 3): its branch nearest it into result, and its index; -1
   when none (result untouched). */
static long first_start(const void *params, int mode, const double *T, const double *Q,
                        Py_ssize_t k, double step, double *result)
{
    const Params *P = params;
    double W[3], X7[3], Z7[3];
    if (mode == 0) pose_frame(P, T, W, X7, Z7);
    for (Py_ssize_t r = 0; r < k; r++) {
        double v[7], sol[8][7];
        int n = 0;
        /* a start with a NaN or an infinity has no joint 1 to keep */
        if (!clip_start(Q + 7 * r, P->lo, P->hi, v)) continue;
        double u[3] = {0.0, 0.0, 0.0}; /* the elbow vector of a position target (mode 1) */
        if (mode == 1) elbow_vector(P, v[4], v[5], v[6], u);
        ElbowWindow window;
        elbow_window(P, mode == 0 ? W : T, mode == 0 ? P->wu : u, &window);
        for (long j = 0; n == 0; j++) {
            int inside_limits = 0;
            for (int sign = 1; sign >= -1 && n == 0; sign -= 2) {
                if (j == 0 && sign < 0) break;
                double q1 = v[0] + sign * (double)j * step;
                if (q1 < P->lo[0] || q1 > P->hi[0]) continue;
                inside_limits = 1;
                if (!elbow_admits(&window, q1 + P->off[0])) continue; /* no elbow: no branch */
                if (mode == 0) {
                    n = pose(P, q1, W, X7, Z7, sol, NULL);
                } else {
                    Arm arms[4];
                    n = arm(P, q1, T, u, NULL, NULL, arms, NULL);
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
        nearest((const double (*)[7])sol, n, v, result);
        return (long)r;
    }
    return -1;
}

#define SEEDED_POINTS 1 /* first_start takes points too */
#include "_seeded7.h"

/* SevenDofIK.prepare in C: mode 0, frame-7 origin and R_0_7 of a world pose; mode 1, a world point
   in frame 0 (K, k: T_world_base of the structure; M, m: its T_last_tool). */
static void prepare_seeded(const Seed *S, int mode, const double *p, const double *r, double *T)
{
    double x[3];
    frame_point(S, p, x);
    if (mode == 1) {
        memcpy(T, x, sizeof x);
        return;
    }
    double *r0 = T + 3;
    frame_rotation(S, r, r0);
    const double *m = S->end_t;
    for (int i = 0; i < 3; i++)
        T[i] = x[i] - (r0[3 * i] * m[0] + r0[3 * i + 1] * m[1] + r0[3 * i + 2] * m[2]);
}

/* The branches at q1 of the form without limits (held_rows in _held7.h), and with fold the
   least fold_distance of the equations solved (*fold: infinity when none). */
static int branches_folds(const Params *P, const double *T, double q1, double (*sol)[7],
                          double *fold)
{
    double W[3], X7[3], Z7[3];
    pose_frame(P, T, W, X7, Z7);
    return pose(P, q1, W, X7, Z7, sol, fold);
}

/* The branches at q1 of the form without limits (all_branches in _branches7.h). */
static int branches_at_value(const Params *P, const double *T, double q1, double (*sol)[7])
{
    return branches_folds(P, T, q1, sol, NULL);
}

#include "_branches7.h"
#include "_held7.h"

static PyObject *first(PyObject *self, PyObject *args)
{
    PyObject *objs[4];
    static const char *const names[4] = {"params", "target", "starts", "out"};
    static const int writable[4] = {0, 0, 0, 1};
    Py_buffer views[4];
    int mode;
    double step;
    (void)self;
    if (!PyArg_ParseTuple(args, "OiOOOd", &objs[0], &mode, &objs[1], &objs[2], &objs[3], &step))
        return NULL;
    if (!get_buffers(4, objs, views, writable, names)) return NULL;
    Py_buffer params = views[0], target = views[1], starts = views[2], out = views[3];
    long found = -1;
    Py_ssize_t need = mode == 0 ? 12 : 3;
    const char *error = check_arrays(&params, PARAM_COUNT, &starts, &out);
    if (error == NULL && mode != 0 && mode != 1) error = "mode must be 0 (pose) or 1 (position)";
    else if (error == NULL && target.len != need * (Py_ssize_t)sizeof(double))
        error = "target: wrong size";
    if (error == NULL)
        found = first_start(params.buf, mode, target.buf, starts.buf,
                            starts.len / (Py_ssize_t)(7 * sizeof(double)), step, out.buf);
    return first_result(4, views, error, found);
}

static PyObject *first_many(PyObject *self, PyObject *args)
{
    (void)self;
    return first_many_call(args, 1, PARAM_COUNT, first_start);
}

static PyMethodDef methods[] = {
    {"first", first, METH_VARARGS,
     "first(params, mode, target, starts, out, step) -> index of the first start with a branch inside "
     "the limits (written to out), or -1. See kin/ik/analytic/seven_r/seven_dof.py."},
    {"first_many", first_many, METH_VARARGS, FIRST_MANY_DOC},
    {"seeded", (PyCFunction)(void (*)(void))seeded, METH_FASTCALL, SEEDED_DOC},
    {"seeded_many", seeded_many, METH_VARARGS, SEEDED_MANY_DOC},
    {"all_branches", (PyCFunction)(void (*)(void))all_branches, METH_FASTCALL, ALL_BRANCHES_DOC},
    {"sift_rows", (PyCFunction)(void (*)(void))sift_rows, METH_FASTCALL, SIFT_ROWS_DOC},
    {"held_rows", (PyCFunction)(void (*)(void))held_rows, METH_FASTCALL, HELD_ROWS_DOC},
    {"skips", set_skips, METH_O, SKIPS_DOC},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_closed7",
                                    "Compiled twin of kin.ik.analytic.seven_dof (optional speed-up).", -1,
                                    methods};

PyMODINIT_FUNC PyInit__closed7(void)
{
    if (results_init() < 0) return NULL;
    PyObject *m = twin_module(&module, FIELDS, sizeof FIELDS / sizeof FIELDS[0], PARAM_COUNT);
    if (m != NULL && add_layout(m, "SEED_LAYOUT", SEED_FIELDS, sizeof SEED_FIELDS / sizeof SEED_FIELDS[0]) < 0)
        Py_CLEAR(m);
    return m;
}

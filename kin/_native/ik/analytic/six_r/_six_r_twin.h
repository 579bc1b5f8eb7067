/*
 * What the compiled twins of the 6R closed forms share (_three_parallel.c, _pieper_arms.c,
 * _general6r.c, its verifier only): the tool pose brought to standard frame 6 in frame 0
 * (_six_r.TargetFrame.scalar), the wrap to
 * (-pi, pi] (_six_r.wrap), and the Python functions of the module:
 *
 * solve(params, positions, rotations, free, out) -> None
 *   params:    float64[PARAM_COUNT], the structure's c_params (its LAYOUT);
 *   positions: float64[N, 3] tool positions in the world [m];
 *   rotations: float64[N, 3, 3] R_world_tool;
 *   free:      the value of the free joint at a singular wrist [rad];
 *   out:       float64[N, 8, 6] receives the branches, NaN rows where a branch does not exist.
 *
 * verify(params, check, position, rotation, seed, free, q, info) -> int
 *   The 8 branches of one target, each moved into the joint limits (the 2 pi copy nearest the
 *   seed, ClosedFormSolver's _wrap, operation for operation), then measured by a plain DH product
 *   of the table (not the closed form's own algebra):
 *   check:     float64[CHECK_COUNT], kin.ik.analytic.six_r_twin.check_params (CHECK_LAYOUT);
 *   position:  float64[3], rotation float64[3, 3]: the target in the world frame;
 *   seed:      float64[6] [rad];
 *   q:         float64[8, 6] receives the joint vectors (NaN rows where no branch);
 *   info:      float64[8, 4] receives per branch: status (0 no branch, 1 valid, 2 outside the
 *              limits, 3 off target), position error [m], rotation error [rad], distance to the
 *              seed [rad].
 *   Returns the number of branches that exist (0: out of reach), or -1 for a target with a value
 *   that is not finite.
 *
 * A twin includes this header, declares its Params (TWIN_PARAMS, with FRAME_PARAMS among its
 * fields), defines
 *   static void solve_one(const Params *P, const double *p, const double *r, double free,
 *                         double out[8][6]);
 * on p_0_6 [m] and R_0_6 (row-major), writing every row (NaN for a missing branch), then includes
 * _six_r_module.h (the two Python functions above and the module set-up).
 */
#ifndef KIN_IK_ANALYTIC_SIX_R_TWIN_H
#define KIN_IK_ANALYTIC_SIX_R_TWIN_H

#include "_twin.h"

#define BRANCHES 8
#define JOINTS 6
#define LIMIT_TOL 1e-10              /* closed_form.LIMIT_TOL */
#define FAST_COPY (M_PI - 1e-9)      /* closed_form._FAST_COPY */
#define FAST_SEED 1e5                /* closed_form._FAST_SEED */

/* _six_r.wrap: angle in (-pi, pi]. Inside it remainder(angle, 2 pi) is angle itself (|angle| <=
   pi = TWO_PI / 2 exactly), so the common case skips the call (a fifth of the solve's time). */
static inline double wrap(double angle)
{
    if (angle > -M_PI && angle <= M_PI) return angle;
    double out = remainder(angle, TWO_PI);
    return out <= -M_PI ? out + TWO_PI : out;
}

/*
 * _six_r.TargetFrame.scalar: p_0_6 and R_0_6 of a world tool pose pw, rw (row-major), with the
 * same sums in the same order. plain[0], plain[1]: 1 when the base, the tool is the identity
 * (skipped, as in Python).
 */
static inline void to_frame6(const double *base_r, const double *base_t, const double *tool_r,
                             const double *tool_t, const double *plain, const double *pw,
                             const double *rw, double *p, double *r)
{
    memcpy(p, pw, 3 * sizeof(double));
    memcpy(r, rw, 9 * sizeof(double));
    if (plain[1] == 0.0) { /* R r_t^T, p - R r_t^T t_t */
        double m[9];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                m[3 * i + j] = r[3 * i] * tool_r[3 * j] + r[3 * i + 1] * tool_r[3 * j + 1] +
                               r[3 * i + 2] * tool_r[3 * j + 2];
        for (int i = 0; i < 3; i++)
            p[i] = p[i] - (m[3 * i] * tool_t[0] + m[3 * i + 1] * tool_t[1] +
                           m[3 * i + 2] * tool_t[2]);
        memcpy(r, m, sizeof m);
    }
    if (plain[0] == 0.0) { /* R_b^T R, R_b^T (p - t_b) */
        double q[3] = {p[0] - base_t[0], p[1] - base_t[1], p[2] - base_t[2]}, m[9];
        for (int j = 0; j < 3; j++) {
            p[j] = base_r[j] * q[0] + base_r[3 + j] * q[1] + base_r[6 + j] * q[2];
            for (int k = 0; k < 3; k++)
                m[3 * j + k] = base_r[j] * r[k] + base_r[3 + j] * r[3 + k] +
                               base_r[6 + j] * r[6 + k];
        }
        memcpy(r, m, sizeof m);
    }
}

/* The frame fields every 6R twin's Params holds (from _six_r.TargetFrame). */
#define FRAME_PARAMS(X)                                              \
    X(base_r, 9, "R of world -> standard frame 0, row-major")        \
    X(base_t, 3, "t of world -> standard frame 0 [m]")               \
    X(tool_r, 9, "R of standard frame 6 -> tool, row-major")         \
    X(tool_t, 3, "t of standard frame 6 -> tool [m]")                \
    X(plain, 2, "1 where the base, the tool is the identity, else 0")

/*
 * The check block: the table's own DH chain (either convention, as written), the joint limits
 * and the tolerances, from kin.ik.analytic.six_r_twin.check_params (CHECK_LAYOUT).
 */
#define CHECK_PARAMS(X)                                                           \
    X(modified, 1, "1 for a modified (Craig) table, 0 for a standard one")        \
    X(a, 6, "a of the table's rows [m]")                                          \
    X(cos_alpha, 6, "cos of the table's twists alpha")                            \
    X(sin_alpha, 6, "sin of the table's twists alpha")                            \
    X(d, 6, "d of the table's rows [m]")                                          \
    X(theta, 6, "theta offsets of the table's rows [rad]")                        \
    X(base, 12, "T_world_base, rows 0-2 of the 4x4, row-major [m]")               \
    X(tool, 12, "T_last_tool, rows 0-2 of the 4x4, row-major [m]")                \
    X(lower, 6, "lower joint limits [rad]")                                       \
    X(upper, 6, "upper joint limits [rad]")                                       \
    X(tolerance, 2, "largest position [m] and rotation [rad] error of a solution") \
    X(has_offsets, 1, "1 when an offset is not 0 (q goes through q + theta - theta)")

#define Check_ENTRY(name, size, doc) TWIN_ENTRY_OF(Check, name, size)
TWIN_BLOCK(Check, CHECK_PARAMS, CHECK_COUNT, CHECK_FIELDS)

/* The larger, the smaller of two numbers that are not NaN (fmax and fmin are library calls unless
   NaN may be ignored; here the joint values, seeds and limits are never NaN). */
static inline double larger(double a, double b) { return a > b ? a : b; }
static inline double smaller(double a, double b) { return a < b ? a : b; }

/* closed_form._nearest_copy: the value + 2 pi k inside the limits nearest the seed, else the
   least outside; *inside tells which. */
static inline double nearest_copy(double value, double seed, double lower, double upper,
                                  int *inside)
{
    double base = value - TWO_PI * nearbyint((value - seed) / TWO_PI);
    double candidates[5] = {base, base - TWO_PI, base + TWO_PI, base - 2 * TWO_PI,
                            base + 2 * TWO_PI};
    double best = base, best_violation = INFINITY, best_distance = INFINITY;
    for (int i = 0; i < 5; i++) {
        double c = candidates[i];
        double violation = larger(larger(lower - LIMIT_TOL - c, c - upper - LIMIT_TOL), 0.0);
        double distance = fabs(c - seed);
        if (violation < best_violation ||
            (violation == best_violation && distance < best_distance)) {
            best = c;
            best_violation = violation;
            best_distance = distance;
        }
    }
    *inside = best_violation == 0.0;
    return best;
}

/* closed_form._wrap: nearest_copy comparing only the candidates that can win. */
static inline double wrap_into(double value, double seed, double lower, double upper, int *inside)
{
    double base = value - TWO_PI * nearbyint((value - seed) / TWO_PI);
    double lower_tol = lower - LIMIT_TOL, candidate, candidate_violation;
    double violation = lower_tol - base;
    if (violation > 0.0) {
        candidate = base + TWO_PI;
        if (lower_tol - candidate > 0.0) return nearest_copy(value, seed, lower, upper, inside);
        candidate_violation = candidate - upper - LIMIT_TOL;
    } else {
        violation = base - upper - LIMIT_TOL;
        if (violation > 0.0) {
            candidate = base - TWO_PI;
            if (candidate - upper - LIMIT_TOL > 0.0)
                return nearest_copy(value, seed, lower, upper, inside);
            candidate_violation = lower_tol - candidate;
        } else if (-FAST_COPY < base - seed && base - seed < FAST_COPY) {
            *inside = 1;
            return base;
        } else {
            return nearest_copy(value, seed, lower, upper, inside);
        }
    }
    if (candidate_violation < 0.0) candidate_violation = 0.0;
    if (candidate_violation < violation ||
        (candidate_violation == violation && fabs(candidate - seed) < fabs(base - seed))) {
        *inside = candidate_violation == 0.0;
        return candidate;
    }
    *inside = 0;
    return base;
}

/* The most branches check_branches_n takes (the general 6R closed form's 16). */
#define CHECK_MAX_BRANCHES 16

/* Each of the `count` (at most CHECK_MAX_BRANCHES) branches q[b] that exists (q[b][0] not NaN)
   moved into the limits in place, then its status, errors and distance to the seed into info[b]
   (a missing branch: zeros). The tool pose of each is the plain product of the table's rows; a
   branch whose first joints equal (bit for bit) those of an earlier one starts from that one's
   product after them (the same operations on the same values: the same pose), so that the wrist
   branches of one arm pose share it. */
static inline void check_branches_n(const Check *C, const double *p, const double *r,
                                    const double *seed, int count, double q[][JOINTS],
                                    double info[][4])
{
    double after[CHECK_MAX_BRANCHES][JOINTS][12]; /* the products through each row, per branch */
    const double *through[CHECK_MAX_BRANCHES][JOINTS]; /* branch b's product through row j (its
                                                          own or that of the branch it shares
                                                          row j with) */
    int present[CHECK_MAX_BRANCHES], n = 0;
    const int modified = C->modified[0] != 0.0;
    for (int b = 0; b < count; b++) {
        if (isnan(q[b][0])) {
            memset(info[b], 0, sizeof info[b]);
            continue;
        }
        int inside = 1;
        double distance2 = 0.0;
        for (int i = 0; i < JOINTS; i++) {
            double value = C->has_offsets[0] != 0.0 ? (q[b][i] + C->theta[i]) - C->theta[i]
                                                    : q[b][i];
            double s = seed[i], low = NAN, high = NAN;
            if (fabs(s) < FAST_SEED) {
                low = larger(C->lower[i], s - FAST_COPY);
                high = smaller(C->upper[i], s + FAST_COPY);
            }
            if (!(low < value && value < high)) {
                int ok;
                value = wrap_into(value, s, C->lower[i], C->upper[i], &ok);
                inside = inside && ok;
            }
            q[b][i] = value;
            distance2 += (value - s) * (value - s);
        }
        int shared = 0, from = -1; /* the longest run of first joints equal to an earlier one's */
        for (int k = 0; k < n; k++) {
            int e = present[k], run = 0;
            while (run < JOINTS - 1 && q[e][run] == q[b][run]) run++;
            if (run > shared) {
                shared = run;
                from = e;
            }
        }
        const double *previous = C->base;
        for (int j = 0; j < shared; j++) previous = through[b][j] = through[from][j];
        for (int j = shared; j < JOINTS; j++) {
            chain_step(modified, C->a[j], C->cos_alpha[j], C->sin_alpha[j], C->d[j],
                       q[b][j] + C->theta[j], previous, after[b][j]);
            previous = through[b][j] = after[b][j];
        }
        present[n++] = b;
        double T[12], position_error, rotation_error;
        chain_compose(previous, C->tool, T);
        pose_errors(T, p, r, &position_error, &rotation_error);
        int on_target = position_error <= C->tolerance[0] && rotation_error <= C->tolerance[1];
        info[b][0] = !on_target ? 3.0 : (inside ? 1.0 : 2.0);
        info[b][1] = position_error;
        info[b][2] = rotation_error;
        info[b][3] = sqrt(distance2);
    }
}

/* check_branches_n of the BRANCHES (8) branches of the two 6R families' twins. */
static inline void check_branches(const Check *C, const double *p, const double *r,
                                  const double *seed, double q[BRANCHES][JOINTS],
                                  double info[BRANCHES][4])
{
    check_branches_n(C, p, r, seed, BRANCHES, q, info);
}

#endif

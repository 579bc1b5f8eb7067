/* The spherical wrist's two flips and the two rows they end: the step every case of the Pieper
 * twin (_pieper_arms.c) shares.
 *
 * From the tool's approach (v) and normal headings in the frame after joint 3, the wrist's
 * cos/sin of joint 5's angle and the wrist's twists, the angles (t4, t5, t6) [rad, before the
 * offsets] of the two flips (sin5 and -sin5). A singular wrist (|(mx, my)| <= 1e-12:
 * _six_r.SINGULAR) takes joint 4 at `free4`. The arithmetic of kin/ik/analytic/six_r/_six_r.py's
 * wrist step, in its order.
 */
#ifndef KIN_WRIST_FLIPS_H
#define KIN_WRIST_FLIPS_H

#include "_six_r_twin.h"

static inline void wrist_flips(double heading4, double cos5, double sin5, double s4, double c4,
                               double s5, double c5, double vx, double vy, double vz,
                               double free4, double angles[2][3])
{
    for (int flip = 0; flip < 2; flip++) {
        double st5 = flip == 0 ? sin5 : -sin5;
        double t5 = atan2(st5, cos5), t4;
        double mx = s5 * st5, my = -(c4 * s5 * cos5 + s4 * c5);
        if (hypot(mx, my) <= 1e-12) /* _six_r.SINGULAR */
            t4 = free4;
        else
            t4 = heading4 - atan2(my, mx);
        double ct4 = cos(t4), st4 = sin(t4);
        double ex = ct4 * vx + st4 * vy, ey = -st4 * vx + ct4 * vy;
        double ez = -s4 * ey + c4 * vz;
        ey = c4 * ey + s4 * vz;
        double ct5 = cos(t5);
        double fx = ct5 * ex + st5 * ey, fy = -st5 * ex + ct5 * ey;
        fy = c5 * fy + s5 * ez;
        angles[flip][0] = t4;
        angles[flip][1] = t5;
        angles[flip][2] = atan2(fy, fx);
    }
}

/* The two rows (wrist no flip, flip) of an arm: q1, q2, q3 [rad] as given, then the flips'
   angles (wrist_flips) less the offsets off[3..5], wrapped; a row with a NaN is NaN whole. */
static inline void wrist_rows_fill(double q1, double q2, double q3, const double angles[2][3],
                                   const double *off, double rows[2][JOINTS])
{
    for (int flip = 0; flip < 2; flip++) {
        double *row = rows[flip];
        row[0] = q1;
        row[1] = q2;
        row[2] = q3;
        row[3] = wrap(angles[flip][0] - off[3]);
        row[4] = wrap(angles[flip][1] - off[4]);
        row[5] = wrap(angles[flip][2] - off[5]);
        int bad = 0;
        for (int j = 0; j < JOINTS; j++) bad |= isnan(row[j]);
        if (bad)
            for (int j = 0; j < JOINTS; j++) row[j] = NAN;
    }
}

#endif

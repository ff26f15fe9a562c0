/* Every quaternion function of the C ABI in double and single precision (this file includes
 * itself twice, once per precision), plus dk_graph_from_edges_len: algebraic identities that
 * hold whatever the implementation (unit norm, q q^-1 = 1, rotation preserves length, the arc
 * maps `from` onto `to`, interpolation end points, axis/angle round trip, average of one
 * rotation and its negative), and bad input returning its status with outputs untouched.
 * Prints "quaternions: every check held" and exits 0, or names the failed check. */
#ifndef REAL
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "deform_kernel.h"

static int failures = 0;

#define CHECK(cond)                                                                       \
    do {                                                                                  \
        if (!(cond)) {                                                                    \
            printf("FAIL line %d: %s\n", __LINE__, #cond);                                \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

#define EXPECT(call, status)                                                              \
    do {                                                                                  \
        dk_status s_ = (call);                                                            \
        if (s_ != (status)) {                                                             \
            printf("FAIL line %d %s: got %d (%s), expected %d\n", __LINE__, #call, (int)s_, \
                   dk_status_str((int32_t)s_), (int)(status));                            \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

#define REAL double
#define SFX(name) name
#define TOL 1e-14
#include "quaternions.c" /* this file, double pass */
#undef REAL
#undef SFX
#undef TOL

#define REAL float
#define SFX(name) name##_f32
#define TOL 2e-6f
#include "quaternions.c" /* this file, float pass */
#undef REAL
#undef SFX
#undef TOL

int main(void) {
    size_t len = 99;
    quat_checks_double();
    quat_checks_float();
    EXPECT(dk_graph_from_edges_len(6, &len), DK_OK);
    CHECK(len == 6);
    len = 99;
    EXPECT(dk_graph_from_edges_len(6, NULL), DK_ERR_NULL_POINTER);
    CHECK(len == 99);
    if (failures) return 1;
    printf("quaternions: every check held\n");
    return 0;
}

#else /* one precision: REAL, SFX, TOL */

#define PASTE_(a, b) a##b
#define PASTE(a, b) PASTE_(a, b)

static REAL PASTE(norm4_, REAL)(const REAL *q) {
    return (REAL)sqrt((double)(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]));
}

static int PASTE(near_, REAL)(REAL a, REAL b) { return fabs((double)(a - b)) <= (double)TOL * 8; }

static int PASTE(untouched_, REAL)(const REAL *v, size_t n) {
    size_t i;
    for (i = 0; i < n; i++)
        if (v[i] != (REAL)777) return 0;
    return 1;
}

static void PASTE(quat_checks_, REAL)(void) {
    const REAL axis[3] = {1, 2, -0.5f}, z[3] = {0, 0, 1};
    const REAL from[3] = {1, 0, 0}, to[3] = {0, 3, 4};
    const REAL pts[6] = {0.3f, -1.2f, 2.5f, 1, 0, 0};
    REAL q[4], p[4], inv[4], prod[4], n[4], arc[4], moved[6], mid[4], ax[3], ang, back[4];
    REAL bad[4] = {777, 777, 777, 777}, out[4] = {777, 777, 777, 777};
    REAL zero[4] = {0, 0, 0, 0}, big[4] = {2, 0, 0, 0}, nanq[4] = {NAN, 0, 0, 0};
    REAL pair[8], w[2] = {1, 2}, avg[4];
    size_t i;
    (void)bad;

    EXPECT(SFX(dk_quat_from_axis_angle)(axis, (REAL)0.7, q), DK_OK);
    CHECK(PASTE(near_, REAL)(PASTE(norm4_, REAL)(q), 1));
    EXPECT(SFX(dk_quat_from_axis_angle)(z, (REAL)0.4, p), DK_OK);

    /* q q^-1 = identity */
    EXPECT(SFX(dk_quat_inverse)(q, inv), DK_OK);
    EXPECT(SFX(dk_quat_mul)(q, inv, prod), DK_OK);
    CHECK(PASTE(near_, REAL)(prod[0], 1) && PASTE(near_, REAL)(prod[1], 0) &&
          PASTE(near_, REAL)(prod[2], 0) && PASTE(near_, REAL)(prod[3], 0));

    /* normalize: unit, same direction */
    EXPECT(SFX(dk_quat_normalize)(big, n), DK_OK);
    CHECK(n[0] == 1 && n[1] == 0 && n[2] == 0 && n[3] == 0);

    /* rotation arc maps from onto to/|to| */
    EXPECT(SFX(dk_quat_rotation_arc)(from, to, arc), DK_OK);
    EXPECT(SFX(dk_quat_rotate_points)(arc, pts, 6, moved, 6), DK_OK);
    CHECK(PASTE(near_, REAL)(moved[3], 0) && PASTE(near_, REAL)(moved[4], (REAL)0.6) &&
          PASTE(near_, REAL)(moved[5], (REAL)0.8));
    /* rotation preserves length */
    CHECK(PASTE(near_, REAL)(moved[0] * moved[0] + moved[1] * moved[1] + moved[2] * moved[2],
                             pts[0] * pts[0] + pts[1] * pts[1] + pts[2] * pts[2]));

    /* interpolation end points, and slerp/nlerp agree at the midpoint up to normalisation */
    EXPECT(SFX(dk_quat_slerp)(q, p, 0, mid), DK_OK);
    for (i = 0; i < 4; i++) CHECK(PASTE(near_, REAL)(mid[i], q[i]));
    EXPECT(SFX(dk_quat_nlerp)(q, p, 1, mid), DK_OK);
    for (i = 0; i < 4; i++) CHECK(PASTE(near_, REAL)(mid[i], p[i]));
    EXPECT(SFX(dk_quat_nlerp)(q, p, (REAL)0.5, mid), DK_OK);
    EXPECT(SFX(dk_quat_slerp)(q, p, (REAL)0.5, back), DK_OK);
    for (i = 0; i < 4; i++) CHECK(PASTE(near_, REAL)(mid[i], back[i]));

    /* axis/angle round trip */
    EXPECT(SFX(dk_quat_to_axis_angle)(p, ax, &ang), DK_OK);
    CHECK(PASTE(near_, REAL)(ang, (REAL)0.4) && PASTE(near_, REAL)(ax[2], 1));

    /* average of q (weight 1) and -q (weight 2) is q up to sign */
    for (i = 0; i < 4; i++) {
        pair[i] = q[i];
        pair[4 + i] = -q[i];
    }
    EXPECT(SFX(dk_quat_average)(pair, 8, w, 2, avg), DK_OK);
    CHECK(PASTE(near_, REAL)(fabs((double)(avg[0] * q[0] + avg[1] * q[1] + avg[2] * q[2] +
                                           avg[3] * q[3])),
                             1));

    /* bad input: status, and the output keeps its sentinel */
    EXPECT(SFX(dk_quat_mul)(NULL, q, out), DK_ERR_NULL_POINTER);
    EXPECT(SFX(dk_quat_mul)(nanq, q, out), DK_ERR_NON_FINITE);
    EXPECT(SFX(dk_quat_normalize)(zero, out), DK_ERR_ZERO_LENGTH);
    EXPECT(SFX(dk_quat_inverse)(zero, out), DK_ERR_ZERO_LENGTH);
    EXPECT(SFX(dk_quat_rotation_arc)(from, zero, out), DK_ERR_ZERO_LENGTH);
    EXPECT(SFX(dk_quat_slerp)(q, nanq, (REAL)0.5, out), DK_ERR_NON_FINITE);
    EXPECT(SFX(dk_quat_nlerp)(q, p, (REAL)NAN, out), DK_ERR_NON_FINITE);
    EXPECT(SFX(dk_quat_average)(pair, 7, NULL, 0, out), DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_quat_average)(pair, 8, w, 1, out), DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_quat_from_axis_angle)(zero, 1, out), DK_ERR_ZERO_LENGTH);
    CHECK(PASTE(untouched_, REAL)(out, 4));
    out[0] = 777;
    EXPECT(SFX(dk_quat_to_axis_angle)(zero, out, &out[3]), DK_ERR_ZERO_LENGTH);
    CHECK(PASTE(untouched_, REAL)(out, 4));
    EXPECT(SFX(dk_quat_to_axis_angle)(q, NULL, &out[3]), DK_ERR_NULL_POINTER);
    EXPECT(SFX(dk_quat_rotate_points)(q, pts, 5, moved, 5), DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_quat_rotate_points)(q, pts, 6, moved, 3), DK_ERR_LENGTH_MISMATCH);
}

#undef PASTE
#undef PASTE_
#endif

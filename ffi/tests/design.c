/* Every design-variable function of the C ABI (dk_design_*) in double and single precision
 * (this file includes itself twice, once per precision): the Hicks-Henne bump peaks at
 * x_max, a bump moves only the chosen side (1-based node indices through index_scratch), an
 * unjittered FFD lattice reproduces its affine map, an FFD_CONTROL_POINT moves one control
 * point, box-minus-box displacements are exactly zero where nothing moved, SU2's
 * SetCartesianCoord displacements vanish for points on the box, an FFD_TWIST turns its layer
 * rigidly about SU2's axis, the derivatives (dk_design_*_adjoint, _twist_tangent) are
 * transposes of the tangents; bad input returns its status
 * with outputs untouched. Prints "design: every check held" and exits 0, or names the
 * failed check. */
#ifndef REAL
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"

#define REAL double
#define SFX(name) name
#define TOL 1e-14
#include "design.c" /* this file, double pass */
#undef REAL
#undef SFX
#undef TOL

#define REAL float
#define SFX(name) name##_f32
#define TOL 1e-5f
#include "design.c" /* this file, float pass */
#undef REAL
#undef SFX
#undef TOL

int main(void) {
    check_();
    check__f32();
    if (failures == 0) printf("design: every check held\n");
    return failures != 0;
}
#else

/* A lattice box of degree (2, 2, 1): P_ijk = (i/2, 2 j/2, k - 0.5) (an affine map). */
static void SFX(lattice)(REAL *cp) {
    int i, j, k, at = 0;
    for (i = 0; i <= 2; i++)
        for (j = 0; j <= 2; j++)
            for (k = 0; k <= 1; k++) {
                cp[at++] = (REAL)i / 2;
                cp[at++] = (REAL)j;
                cp[at++] = (REAL)k - (REAL)0.5;
            }
}

static void SFX(check_hicks_henne)(void) {
    REAL peak = 0, pts[6] = {0.5, 0.1, 0.5, -0.1, 0.25, 0.0};
    REAL normals[4] = {0, 1, 0, -1}, d[4] = {0, 0, 0, 0}, keep[4];
    uint32_t nodes[2] = {1, 2}, scratch[2];
    OK(SFX(dk_design_hicks_henne_bump)((REAL)0.3, (REAL)0.3, &peak));
    CHECK(fabs((double)peak - 1.0) < TOL);
    OK(SFX(dk_design_hicks_henne)(pts, 6, 2, nodes, 2, 1, scratch, 2, normals, 4, true,
                                  (REAL)0.5, (REAL)0.01, d, 4));
    CHECK(fabs((double)d[1] - 0.01) < TOL && d[0] == 0 && d[2] == 0 && d[3] == 0);
    memcpy(keep, d, sizeof d);
    EXPECT(SFX(dk_design_hicks_henne)(pts, 6, 2, nodes, 2, 1, scratch, 2, normals, 4, false,
                                      (REAL)1.0, (REAL)0.01, d, 4),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_design_hicks_henne)(pts, 6, 2, nodes, 2, 1, NULL, 0, normals, 4, false,
                                      (REAL)0.5, (REAL)0.01, d, 4),
           DK_ERR_BUFFER_TOO_SMALL);
    SAME(keep, d, sizeof d);
}

static void SFX(check_ffd)(void) {
    uint32_t degree[3] = {2, 2, 1}, nodes[3] = {0, 1, 2};
    int32_t index[3] = {1, 1, 0}, all[3] = {-1, -1, -1};
    REAL cp[54], moved[54], uvw[9] = {0.25, 0.5, 0.5, 1.0, 0.0, 0.0, 0.6, 0.3, 0.9};
    REAL x[9], d[9], keep[9], move[3] = {0, (REAL)0.1, 0};
    int p, c, changed = 0;
    SFX(lattice)(cp);
    OK(SFX(dk_design_ffd_eval)(degree, 3, cp, 54, 3, uvw, 9, x, 9));
    for (p = 0; p < 3; p++) {
        CHECK(fabs((double)(x[3 * p] - uvw[3 * p] )) < TOL);
        CHECK(fabs((double)(x[3 * p + 1] - 2 * uvw[3 * p + 1])) < TOL);
        CHECK(fabs((double)(x[3 * p + 2] - (uvw[3 * p + 2] - (REAL)0.5))) < TOL);
    }
    memcpy(moved, cp, sizeof cp);
    OK(SFX(dk_design_ffd_variable)(DK_FFD_CONTROL_POINT, degree, moved, 54, index, move));
    for (c = 0; c < 54; c++) changed += moved[c] != cp[c];
    CHECK(changed == 1 && moved[3 * 8 + 1] == cp[3 * 8 + 1] + (REAL)0.1);
    memcpy(keep, moved, sizeof keep);
    EXPECT(SFX(dk_design_ffd_variable)(DK_FFD_CONTROL_POINT, degree, moved, 54, all, move),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_design_ffd_variable)(99, degree, moved, 54, index, move),
           DK_ERR_INVALID_PARAMETER);
    SAME(keep, moved, sizeof keep);
    OK(SFX(dk_design_ffd_displacements_between)(degree, 3, cp, 54, moved, 54, 3, uvw, 9, d, 9));
    CHECK(d[0] == 0 && d[2] == 0 && d[1] > 0 && d[3] == 0 && d[4] == 0 && d[5] == 0);
    OK(SFX(dk_design_ffd_displacements)(degree, 3, cp, 54, 3, x, 9, nodes, 3, 0, NULL, 0, uvw,
                                        9, d, 9));
    for (c = 0; c < 9; c++) CHECK(d[c] == 0);
    memcpy(keep, d, sizeof keep);
    degree[0] = 0;
    EXPECT(SFX(dk_design_ffd_eval)(degree, 3, cp, 54, 3, uvw, 9, d, 9),
           DK_ERR_INVALID_PARAMETER);
    SAME(keep, d, sizeof keep);
}

/* FFD_TWIST on the lattice: layer j = 1 (y = 1) turns by atan(0.1 / 1) about the y-parallel
 * axis through (0.5, 1, 0), where the segment crosses y = 1; the other layers, y, the distance
 * from the axis and the points with i = 0 (fixed_i) stay. */
static void SFX(check_twist)(void) {
    uint32_t degree[3] = {2, 2, 1}, fixed_i[1] = {0};
    REAL cp[54], moved[54], keep[54], seg[6] = {0.5, -1, 0, 0.5, 3, 0};
    int i, j, k, at = 0;
    SFX(lattice)(cp);
    memcpy(moved, cp, sizeof cp);
    OK(SFX(dk_design_ffd_twist)(degree, moved, 54, 1, seg, (REAL)0.1, (REAL)1.0, fixed_i, 1,
                                NULL, 0));
    for (i = 0; i <= 2; i++)
        for (j = 0; j <= 2; j++)
            for (k = 0; k <= 1; k++, at += 3) {
                double ax = cp[at] - 0.5, az = cp[at + 2], bx = moved[at] - 0.5,
                       bz = moved[at + 2];
                CHECK(moved[at + 1] == cp[at + 1]);
                if (j != 1 || i == 0) {
                    CHECK(moved[at] == cp[at] && moved[at + 2] == cp[at + 2]);
                    continue;
                }
                CHECK(fabs(sqrt(ax * ax + az * az) - sqrt(bx * bx + bz * bz)) < 10 * TOL);
                CHECK(fabs((ax * bx + az * bz) / (ax * ax + az * az) - 1 / sqrt(1.01)) <
                      10 * TOL);
            }
    memcpy(keep, moved, sizeof keep);
    EXPECT(SFX(dk_design_ffd_twist)(degree, moved, 54, 1, seg, (REAL)0.1, (REAL)0.0, NULL, 0,
                                    NULL, 0),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_design_ffd_twist)(degree, moved, 54, 7, seg, (REAL)0.1, (REAL)1.0, NULL, 0,
                                    NULL, 0),
           DK_ERR_INDEX_OUT_OF_RANGE);
    SAME(keep, moved, sizeof keep);
}

/* The derivatives (dk_design_*_adjoint, dk_design_ffd_twist_tangent): the adjoints equal the
 * tangents' dot products (a bump of amplitude 1; the box of a change evaluated), the twist's
 * tangent turns layer j about the pivot (perpendicular to p - pivot, y fixed); bad input
 * leaves out unchanged. */
static void SFX(check_derivatives)(void) {
    uint32_t degree[3] = {2, 2, 1}, nodes[2] = {1, 2}, scratch[2];
    REAL pts[6] = {0.5, 0.1, 0.5, -0.1, 0.25, 0.0}, normals[4] = {0, 1, 0, -1};
    REAL g[9] = {0.3, -0.7, 0.2, 0.9, 0.4, -0.5, 0.1, 0.8, -0.6}, d[4] = {0, 0, 0, 0};
    REAL uvw[9] = {0.25, 0.5, 0.5, 1.0, 0.0, 0.0, 0.6, 0.3, 0.9}, cp[54], v[9], bar[54];
    REAL seg[6] = {0.5, -1, 0, 0.5, 3, 0}, t[54], keep[54], adj = 0;
    double lhs = 0, rhs = 0;
    int c;
    OK(SFX(dk_design_hicks_henne)(pts, 6, 2, nodes, 2, 1, scratch, 2, normals, 4, false,
                                  (REAL)0.3, (REAL)1.0, d, 4));
    OK(SFX(dk_design_hicks_henne_adjoint)(pts, 6, 2, nodes, 2, 1, scratch, 2, normals, 4,
                                          false, (REAL)0.3, g, 4, &adj));
    CHECK(adj != 0 && fabs((double)(d[3] * g[3] - adj)) < TOL);
    for (c = 0; c < 54; c++) cp[c] = (REAL)sin(c + 1.0);
    OK(SFX(dk_design_ffd_eval)(degree, 3, cp, 54, 3, uvw, 9, v, 9));
    OK(SFX(dk_design_ffd_adjoint)(degree, 3, 3, uvw, 9, g, 9, bar, 54));
    for (c = 0; c < 9; c++) lhs += (double)(v[c] * g[c]);
    for (c = 0; c < 54; c++) rhs += (double)(cp[c] * bar[c]);
    CHECK(fabs(lhs) > 0.1 && fabs(lhs - rhs) < 10 * TOL * fabs(lhs));
    SFX(lattice)(cp);
    OK(SFX(dk_design_ffd_twist_tangent)(degree, cp, 54, 1, seg, (REAL)2.0, NULL, 0, NULL, 0,
                                        t, 54));
    for (c = 0; c < 54; c += 3) {
        int layer = (c / 6) % 3 == 1;
        CHECK(t[c + 1] == 0 && (layer ? t[c] != 0 || t[c + 2] != 0 : t[c] == 0 && t[c + 2] == 0));
        CHECK(fabs((double)(t[c] * (cp[c] - (REAL)0.5) + t[c + 2] * cp[c + 2])) < TOL);
    }
    memcpy(keep, bar, sizeof keep);
    EXPECT(SFX(dk_design_ffd_adjoint)(degree, 3, 3, uvw, 9, g, 6, bar, 54),
           DK_ERR_LENGTH_MISMATCH);
    SAME(keep, bar, sizeof keep);
}

static void SFX(check_)(void) {
    SFX(check_hicks_henne)();
    SFX(check_ffd)();
    SFX(check_twist)();
    SFX(check_derivatives)();
}
#endif

/* The rigid wall layer from C99: dk_elasticity_rigid_layer (double, 0-based wall) and
 * dk_elasticity_rigid_layer_f32 (float, 1-based wall with its index scratch) on a 5 x 5 node
 * square whose bottom row is the wall, turned 10 degrees about the origin (one rotation per
 * wall node, scalar first; the wall's displacement R x - x already in `displacement`), with a
 * layer of 0.3 (the second row at y = 0.25 joins it, the third at 0.5 does not).
 *
 * Prints the fixed masks, the displacements and the `added` counts, so
 * host-tests/tests/ffi/c_abi_elasticity_layer.rs can compute the same with the kernel's
 * `elasticity::rigid_layer` and compare the text. Checks here: the second row is marked and
 * moves by R x - x (to rounding), the rows above stay free and unmoved, and bad input (a
 * negative or NaN thickness, dim 4, a wall index out of range, a short `fixed`, index base 1
 * without scratch) returns its status and writes nothing. Ends with "elasticity_layer: every
 * check held" (exit 0), or prints each failed check (exit 1). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

#define S 5
#define N (S * S)

static double points[2 * N], disp[2 * N], rot[4 * S];
static float points32[2 * N], disp32[2 * N], rot32[4 * S];
static uint8_t fixed[N], fixed32[N];
static uint32_t wall[S], wall1[S];

static void build(void) {
    const double t = 10.0 * 3.14159265358979323846 / 180.0, c = cos(t), s = sin(t);
    size_t i, j;
    for (j = 0; j < S; j++) {
        for (i = 0; i < S; i++) {
            size_t n = i + S * j;
            double x = 0.25 * (double)i, y = 0.25 * (double)j;
            points[2 * n] = x;
            points[2 * n + 1] = y;
            fixed[n] = (uint8_t)(j == 0);
            disp[2 * n] = j == 0 ? c * x - s * y - x : 0.0;
            disp[2 * n + 1] = j == 0 ? s * x + c * y - y : 0.0;
        }
    }
    for (i = 0; i < S; i++) {
        wall[i] = (uint32_t)i;
        wall1[i] = (uint32_t)i + 1;
        rot[4 * i] = cos(t / 2);
        rot[4 * i + 1] = 0.0;
        rot[4 * i + 2] = 0.0;
        rot[4 * i + 3] = sin(t / 2);
    }
    for (i = 0; i < 2 * N; i++) {
        points32[i] = (float)points[i];
        disp32[i] = (float)disp[i];
    }
    for (i = 0; i < 4 * S; i++) rot32[i] = (float)rot[i];
    memcpy(fixed32, fixed, sizeof fixed);
}

/* Bad input: each call returns its status and leaves `fixed` and `disp` as they were. */
static void bad_input(void) {
    uint8_t f0[N];
    double d0[2 * N];
    uint32_t far[S] = {0, 1, 2, 3, N};
    size_t added = 7;
    memcpy(f0, fixed, sizeof f0);
    memcpy(d0, disp, sizeof d0);
    EXPECT(dk_elasticity_rigid_layer(points, 2 * N, 2, wall, S, 0, NULL, 0, rot, 4 * S, -0.1,
                                     fixed, N, disp, 2 * N, &added),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_rigid_layer(points, 2 * N, 2, wall, S, 0, NULL, 0, rot, 4 * S, NAN,
                                     fixed, N, disp, 2 * N, &added),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_rigid_layer(points, 2 * N, 4, wall, S, 0, NULL, 0, rot, 4 * S, 0.3,
                                     fixed, N, disp, 2 * N, &added),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_rigid_layer(points, 2 * N, 2, far, S, 0, NULL, 0, rot, 4 * S, 0.3,
                                     fixed, N, disp, 2 * N, &added),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(dk_elasticity_rigid_layer(points, 2 * N, 2, wall, S, 0, NULL, 0, rot, 4 * S, 0.3,
                                     fixed, N - 1, disp, 2 * N, &added),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_elasticity_rigid_layer(points, 2 * N, 2, wall1, S, 1, NULL, 0, rot, 4 * S, 0.3,
                                     fixed, N, disp, 2 * N, &added),
           DK_ERR_BUFFER_TOO_SMALL);
    SAME(f0, fixed, sizeof f0);
    SAME(d0, disp, sizeof d0);
    CHECK(added == 7);
}

int main(void) {
    const double t = 10.0 * 3.14159265358979323846 / 180.0, c = cos(t), s = sin(t);
    uint32_t scratch[S];
    size_t added = 0, added32 = 0, k;
    build();
    hex64("points", points, 2 * N);
    hex64("rotation", rot, 4);
    hex64("initial", disp, 2 * N);
    bad_input();
    OK(dk_elasticity_rigid_layer(points, 2 * N, 2, wall, S, 0, NULL, 0, rot, 4 * S, 0.3, fixed,
                                 N, disp, 2 * N, &added));
    OK(dk_elasticity_rigid_layer_f32(points32, 2 * N, 2, wall1, S, 1, scratch, S, rot32, 4 * S,
                                     0.3f, fixed32, N, disp32, 2 * N, &added32));
    CHECK(added == S && added32 == S);
    for (k = 0; k < N; k++) {
        double x = points[2 * k], y = points[2 * k + 1];
        int in = k < 2 * S;
        CHECK(fixed[k] == in && fixed32[k] == in);
        CHECK(fabs(disp[2 * k] - (in ? c * x - s * y - x : 0.0)) < 1e-15);
        CHECK(fabs(disp[2 * k + 1] - (in ? s * x + c * y - y : 0.0)) < 1e-15);
        CHECK(fabs(disp32[2 * k] - disp[2 * k]) < 1e-6);
    }
    printf("f64 added %zu fixed", added);
    for (k = 0; k < N; k++) printf(" %d", fixed[k]);
    printf("\n");
    hex64("f64 displacement", disp, 2 * N);
    printf("f32 added %zu fixed", added32);
    for (k = 0; k < N; k++) printf(" %d", fixed32[k]);
    printf("\n");
    hex32("f32 displacement", disp32, 2 * N);
    if (failures) return 1;
    printf("elasticity_layer: every check held\n");
    return 0;
}

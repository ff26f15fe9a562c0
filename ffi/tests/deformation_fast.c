/* The fast (tree) IDW deformation and its derivatives from C99: dk_deform_idw_fast_lens,
 * dk_deform_idw_fast, dk_deform_idw_fast_tangent, dk_deform_idw_fast_adjoint (f64 and f32) on
 * a warped 16 x 12 grid whose perimeter (52 nodes, a loop of segments, rotations from the
 * shape) turns by 0.08 rad and bulges.
 *
 * Prints the inputs (points, deformed boundary, direction, weights) and, per precision, the
 * bits of the deformed mesh, the bound, the tangent and the adjoint, so
 * host-tests/tests/ffi/c_abi_deformation_fast.rs can compute the same with the kernel and
 * compare the text. Checks here: boundary nodes bitwise at their prescribed positions, the
 * bound within the tolerance, <J v, w> = <v, J^T w>, and bad input (dim, theta, tolerance,
 * exponent, short tree/index/scratch, NaN fields, wrong lengths, NULL) returns its status and
 * leaves every output untouched. The per-precision part is deformation_fast_body.c. Ends
 * with "deformation_fast: every check held" (exit 0), or prints each failed check (exit 1). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

#define MX 16
#define MY 12
#define N (MX * MY)
#define B (2 * (MX + MY) - 4)
#define WORK 8192

static double P[2 * N], DEF[2 * B], DIR[2 * B], W[2 * N];
static uint32_t ring[B], seg_offsets[B + 1], seg_nodes[2 * B];
static uint8_t seg_kinds[B];

/* The grid (warped), its perimeter in order, the loop of segments and the motion. */
static void setup(void) {
    size_t i, k = 0;
    const double a = 0.08, c = cos(a), s = sin(a);
    for (i = 0; i < N; i++) {
        double x = (double)(i % MX) / (MX - 1), y = (double)(i / MX) / (MY - 1);
        P[2 * i] = 1.1 * x + 0.04 * sin(3.0 * y);
        P[2 * i + 1] = 0.9 * y + 0.03 * sin(2.0 * x);
    }
    for (i = 0; i < MX; i++) ring[k++] = (uint32_t)i;
    for (i = 1; i < MY; i++) ring[k++] = (uint32_t)(MX - 1 + MX * i);
    for (i = MX - 1; i-- > 0;) ring[k++] = (uint32_t)(i + MX * (MY - 1));
    for (i = MY - 1; i-- > 1;) ring[k++] = (uint32_t)(MX * i);
    for (i = 0; i < B; i++) {
        double x = P[2 * ring[i]] - 0.55, y = P[2 * ring[i] + 1] - 0.45;
        DEF[2 * i] = 0.55 + c * x - s * y + 0.02 * sin(4.0 * y);
        DEF[2 * i + 1] = 0.45 + s * x + c * y + 0.015 * sin(5.0 * x);
        seg_offsets[i] = (uint32_t)(2 * i);
        seg_nodes[2 * i] = (uint32_t)i;
        seg_nodes[2 * i + 1] = (uint32_t)((i + 1) % B);
        seg_kinds[i] = 3;
        DIR[2 * i] = sin(0.3 + 1.1 * (double)i);
        DIR[2 * i + 1] = sin(1.7 + 0.6 * (double)i);
    }
    seg_offsets[B] = 2 * B;
    for (i = 0; i < 2 * N; i++) W[i] = cos(0.2 + 0.9 * (double)i);
}

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)

#define REAL double
#define FN(name) name
#define SUF f64
#define HEX hex64
#define TOL 1e-12
#include "deformation_fast_body.c"
#undef REAL
#undef FN
#undef SUF
#undef HEX
#undef TOL

#define REAL float
#define FN(name) name##_f32
#define SUF f32
#define HEX hex32
#define TOL 1e-4
#include "deformation_fast_body.c"

int main(void) {
    setup();
    hex64("points", P, 2 * N);
    hex64("deformed", DEF, 2 * B);
    hex64("direction", DIR, 2 * B);
    hex64("weights", W, 2 * N);
    run_f64();
    run_f32();
    if (failures != 0) return 1;
    printf("deformation_fast: every check held\n");
    return 0;
}

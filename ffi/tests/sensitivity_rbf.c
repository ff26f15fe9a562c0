/* The RBF sensitivities from C99: dk_sensitivity_rbf_tangent and dk_sensitivity_rbf_adjoint
 * (and _f32) on a 7 x 7 node jittered square whose outer ring is the boundary, linearised
 * about a smooth boundary motion: thin-plate splines with greedy centres (at most 12) and the
 * wall correction in double with 0-based boundary nodes, Wendland with every centre and no
 * correction in float with 1-based ones.
 *
 * Prints the inputs and the bits of every result, so
 * host-tests/tests/ffi/c_abi_sensitivity_rbf.rs can compute the same with the kernel and
 * compare the text. Checks here: the dot-product identity <J v, w> = <v, J^T w>, and bad input
 * (a short output, dim 4) returns its status and leaves the output untouched. Ends with
 * "sensitivity_rbf: every check held" (exit 0). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

#define S 7
#define N (S * S)
#define NB (4 * (S - 1))

static double points[2 * N], w[2 * N], motion[2 * NB], v[2 * NB];
static float points32[2 * N], w32[2 * N], motion32[2 * NB], v32[2 * NB];
static uint32_t boundary[NB], boundary1[NB];

static void build(void) {
    size_t i, j, b = 0;
    for (j = 0; j < S; j++) {
        for (i = 0; i < S; i++) {
            size_t n = i + S * j;
            int edge = i == 0 || j == 0 || i == S - 1 || j == S - 1;
            points[2 * n] = ((double)i + (edge ? 0.0 : 0.05 * (double)((n * 7) % 5) - 0.1)) / (S - 1);
            points[2 * n + 1] = ((double)j + (edge ? 0.0 : 0.04 * (double)((n * 3) % 5) - 0.08)) / (S - 1);
            w[2 * n] = sin(1.0 + (double)n);
            w[2 * n + 1] = cos(2.0 * (double)n);
            if (edge) {
                double x = points[2 * n], y = points[2 * n + 1];
                motion[2 * b] = 0.05 * sin(3.0 * y) + 0.1 * exp(-10.0 * ((x - 1) * (x - 1) + (y - 0.3) * (y - 0.3)));
                motion[2 * b + 1] = 0.05 * sin(3.0 * x) + 0.02 * x * y;
                v[2 * b] = 0.5 - 0.1 * (double)(n % 7);
                v[2 * b + 1] = 0.05 * (double)(n % 5);
                boundary[b] = (uint32_t)n;
                boundary1[b++] = (uint32_t)n + 1;
            }
        }
    }
    for (i = 0; i < 2 * N; i++) {
        points32[i] = (float)points[i];
        w32[i] = (float)w[i];
    }
    for (i = 0; i < 2 * NB; i++) {
        motion32[i] = (float)motion[i];
        v32[i] = (float)v[i];
    }
}

static double dot(const double *a, const double *b, size_t n) {
    double s = 0.0;
    size_t i;
    for (i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

int main(void) {
    size_t len = 0, ilen = 0;
    double jv[2 * N], g[2 * NB], g0[2 * NB], *s;
    float jv32[2 * N], g32[2 * NB], *s32;
    uint32_t *index;
    dk_rbf_options o;
    build();
    hex64("points", points, 2 * N);
    hex64("w", w, 2 * N);
    hex64("motion", motion, 2 * NB);
    hex64("v", v, 2 * NB);

    /* Sized for the larger use: every boundary node a centre, 1-based. */
    OK(dk_rbf_options_default(&o));
    OK(dk_rbf_scratch_len(NB, 2, &o, &len));
    OK(dk_rbf_index_scratch_len(NB, 2, 1, &o, &ilen));
    o.kernel = DK_RBF_THIN_PLATE;
    o.tolerance = 1e-3;
    o.max_centres = 12;
    o.correction_radius = 0.4;
    s = xmalloc(len * sizeof(double));
    s32 = xmalloc(len * sizeof(float));
    index = xmalloc(ilen * sizeof(uint32_t));
    OK(dk_sensitivity_rbf_tangent(points, 2 * N, 2, boundary, NB, 0, motion, 2 * NB, &o, index,
                                  ilen, s, len, v, 2 * NB, jv, 2 * N));
    OK(dk_sensitivity_rbf_adjoint(points, 2 * N, 2, boundary, NB, 0, motion, 2 * NB, &o, index,
                                  ilen, s, len, w, 2 * N, g, 2 * NB));
    CHECK(fabs(dot(jv, w, 2 * N) - dot(v, g, 2 * NB)) <=
          1e-13 * sqrt(dot(jv, jv, 2 * N) * dot(w, w, 2 * N)));
    hex64("rbf tangent f64", jv, 2 * N);
    hex64("rbf adjoint f64", g, 2 * NB);

    OK(dk_rbf_options_default(&o));
    o.radius = 0.8;
    OK(dk_sensitivity_rbf_tangent_f32(points32, 2 * N, 2, boundary1, NB, 1, motion32, 2 * NB, &o,
                                      index, ilen, s32, len, v32, 2 * NB, jv32, 2 * N));
    OK(dk_sensitivity_rbf_adjoint_f32(points32, 2 * N, 2, boundary1, NB, 1, motion32, 2 * NB, &o,
                                      index, ilen, s32, len, w32, 2 * N, g32, 2 * NB));
    hex32("rbf tangent f32", jv32, 2 * N);
    hex32("rbf adjoint f32", g32, 2 * NB);

    /* Bad input: nothing written. */
    memcpy(g0, g, sizeof g);
    EXPECT(dk_sensitivity_rbf_adjoint(points, 2 * N, 2, boundary, NB, 0, motion, 2 * NB, &o,
                                      index, ilen, s, len, w, 2 * N, g, 2 * NB - 2),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_sensitivity_rbf_adjoint(points, 2 * N, 4, boundary, NB, 0, motion, 2 * NB, &o,
                                      index, ilen, s, len, w, 2 * N, g, 2 * NB),
           DK_ERR_INVALID_PARAMETER);
    SAME(g, g0, sizeof g);
    free(s);
    free(s32);
    free(index);
    printf("sensitivity_rbf: every check held\n");
    return 0;
}

/* Mesh sensitivities from C99: dk_sensitivity_spring_adjoint_scratch_len,
 * dk_sensitivity_spring_adjoint (and _f32), dk_sensitivity_idw_tangent and
 * dk_sensitivity_idw_adjoint (and _f32) on a 6 x 6 node jittered square, its boundary fixed,
 * Batina stiffness from dk_spring_batina_stiffness: the spring adjoint of a field w (two
 * components) with CG + Jacobi, the IDW tangent of a boundary perturbation v and the IDW
 * adjoint of w with exponent 2, in double with 0-based boundary nodes and in float with
 * 1-based ones.
 *
 * Prints the inputs and the bits of every result, so host-tests/tests/ffi/c_abi_sensitivity.rs
 * can compute the same with the kernel and compare the text. Checks here: the dot-product
 * identity <J v, w> = <v, J^T w> of the IDW pair, zero adjoint at the free nodes, and bad
 * input (a stationary method, a short scratch, dim 4, index base 2) returns its status and
 * leaves the output untouched. Ends with "sensitivity: every check held" (exit 0). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

#define S 6
#define N (S * S)
#define NB (4 * (S - 1))

static double points[2 * N], w[2 * N], v[2 * N];
static float points32[2 * N], w32[2 * N], v32[2 * N];
static uint8_t fixed[N];
static uint32_t offsets[N + 1], targets[4 * N], boundary[NB], boundary1[NB];

/* Grid points (interior jittered), 4-neighbour CSR graph in sorted order, the fields. */
static void build(void) {
    size_t i, j, k = 0, b = 0;
    offsets[0] = 0;
    for (j = 0; j < S; j++) {
        for (i = 0; i < S; i++) {
            size_t n = i + S * j;
            int edge = i == 0 || j == 0 || i == S - 1 || j == S - 1;
            double jx = edge ? 0.0 : 0.05 * (double)((n * 7) % 5) - 0.1;
            double jy = edge ? 0.0 : 0.04 * (double)((n * 3) % 5) - 0.08;
            points[2 * n] = ((double)i + jx) / (S - 1);
            points[2 * n + 1] = ((double)j + jy) / (S - 1);
            fixed[n] = (uint8_t)edge;
            if (edge) {
                boundary[b] = (uint32_t)n;
                boundary1[b++] = (uint32_t)n + 1;
            }
            w[2 * n] = sin(1.0 + (double)n);
            w[2 * n + 1] = cos(2.0 * (double)n);
            v[2 * n] = edge ? 0.5 - 0.1 * (double)(n % 7) : 0.0;
            v[2 * n + 1] = edge ? 0.05 * (double)(n % 5) : 0.0;
            if (j > 0) targets[k++] = (uint32_t)(n - S);
            if (i > 0) targets[k++] = (uint32_t)(n - 1);
            if (i + 1 < S) targets[k++] = (uint32_t)(n + 1);
            if (j + 1 < S) targets[k++] = (uint32_t)(n + S);
            offsets[n + 1] = (uint32_t)k;
        }
    }
    for (i = 0; i < 2 * N; i++) {
        points32[i] = (float)points[i];
        w32[i] = (float)w[i];
        v32[i] = (float)v[i];
    }
}

static double dot(const double *a, const double *b) {
    double s = 0.0;
    size_t i;
    for (i = 0; i < 2 * N; i++) s += a[i] * b[i];
    return s;
}

static void springs(void) {
    size_t e = offsets[N], len = 0, i;
    dk_graph graph = {offsets, N + 1, targets, e};
    double *k = xmalloc(e * sizeof(double)), g[2 * N], g0[2 * N];
    float *k32 = xmalloc(e * sizeof(float)), g32[2 * N];
    uint32_t index[N];
    dk_spring_solve_options o;
    dk_spring_solve_report r;
    OK(dk_spring_batina_stiffness(&graph, points, 2 * N, 2, 1.0, k, e));
    OK(dk_spring_batina_stiffness_f32(&graph, points32, 2 * N, 2, 1.0f, k32, e));
    dk_spring_system sys = {graph, k, e, fixed, N};
    dk_spring_system_f32 sys32 = {graph, k32, e, fixed, N};
    OK(dk_spring_solve_options_default(&o));
    o.residual_tol = 1e-13;
    OK(dk_sensitivity_spring_adjoint_scratch_len(N, 2, &o, &len));
    double *s = xmalloc(len * sizeof(double));
    float *s32 = xmalloc(len * sizeof(float));
    OK(dk_sensitivity_spring_adjoint(&sys, &o, 2, w, 2 * N, g, 2 * N, s, len, index, N, &r));
    CHECK(r.converged);
    for (i = 0; i < N; i++) CHECK(fixed[i] || (g[2 * i] == 0.0 && g[2 * i + 1] == 0.0));
    hex64("spring f64", g, 2 * N);
    printf("spring f64 report %zu %d\n", r.iterations, (int)r.converged);
    OK(dk_spring_solve_options_default_f32(&o));
    OK(dk_sensitivity_spring_adjoint_f32(&sys32, &o, 2, w32, 2 * N, g32, 2 * N, s32, len, index,
                                         N, &r));
    hex32("spring f32", g32, 2 * N);
    printf("spring f32 report %zu %d\n", r.iterations, (int)r.converged);
    /* Bad input: nothing written. */
    memcpy(g0, g, sizeof g);
    EXPECT(dk_sensitivity_spring_adjoint(&sys, &o, 2, w, 2 * N, g, 2 * N, s, len - 1, index, N,
                                         &r),
           DK_ERR_BUFFER_TOO_SMALL);
    o.method = DK_LINEAR_SOR;
    EXPECT(dk_sensitivity_spring_adjoint_scratch_len(N, 2, &o, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_sensitivity_spring_adjoint(&sys, &o, 2, w, 2 * N, g, 2 * N, s, len, index, N, &r),
           DK_ERR_INVALID_PARAMETER);
    SAME(g, g0, sizeof g);
    free(k);
    free(k32);
    free(s);
    free(s32);
}

static void idw(void) {
    double jv[2 * N], g[2 * N], g0[2 * N];
    float jv32[2 * N], g32[2 * N];
    uint32_t index[NB];
    memcpy(jv, v, sizeof v);
    OK(dk_sensitivity_idw_tangent(points, 2 * N, 2, boundary, NB, 0, NULL, 0, 2.0, jv, 2 * N));
    OK(dk_sensitivity_idw_adjoint(points, 2 * N, 2, boundary, NB, 0, NULL, 0, 2.0, w, 2 * N, g,
                                  2 * N));
    CHECK(fabs(dot(jv, w) - dot(v, g)) <= 1e-13 * (fabs(dot(jv, w)) + 1.0));
    hex64("idw tangent f64", jv, 2 * N);
    hex64("idw adjoint f64", g, 2 * N);
    memcpy(jv32, v32, sizeof v32);
    OK(dk_sensitivity_idw_tangent_f32(points32, 2 * N, 2, boundary1, NB, 1, index, NB, 2.0f, jv32,
                                      2 * N));
    OK(dk_sensitivity_idw_adjoint_f32(points32, 2 * N, 2, boundary1, NB, 1, index, NB, 2.0f, w32,
                                      2 * N, g32, 2 * N));
    hex32("idw tangent f32", jv32, 2 * N);
    hex32("idw adjoint f32", g32, 2 * N);
    memcpy(g0, g, sizeof g);
    EXPECT(dk_sensitivity_idw_adjoint(points, 2 * N, 4, boundary, NB, 0, NULL, 0, 2.0, w, 2 * N,
                                      g, 2 * N),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_sensitivity_idw_adjoint(points, 2 * N, 2, boundary, NB, 2, index, NB, 2.0, w, 2 * N,
                                      g, 2 * N),
           DK_ERR_BAD_INDEX_BASE);
    EXPECT(dk_sensitivity_idw_adjoint(points, 2 * N, 2, boundary, NB, 0, NULL, 0, -1.0, w, 2 * N,
                                      g, 2 * N),
           DK_ERR_INVALID_PARAMETER);
    SAME(g, g0, sizeof g);
}

int main(void) {
    build();
    hex64("points", points, 2 * N);
    hex64("w", w, 2 * N);
    hex64("v", v, 2 * N);
    springs();
    idw();
    if (failures) return 1;
    printf("sensitivity: every check held\n");
    return 0;
}

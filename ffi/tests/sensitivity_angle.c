/* The angle-spring sensitivities from C99: dk_sensitivity_angle_adjoint_scratch_len and
 * dk_sensitivity_angle_adjoint (and _f32) on a 6 x 6 node jittered square cut into triangles
 * (one diagonal per quad), its boundary fixed, Batina stiffness: the adjoint of a field w
 * with block-Jacobi CG, and the tangent of a boundary perturbation v (dk_spring_solve_angle
 * itself, the map being linear), in double with epsilon 0 (the rigidity probe runs) and in
 * float with the default epsilon 0.01.
 *
 * Prints the inputs and the bits of every result, so
 * host-tests/tests/ffi/c_abi_sensitivity_angle.rs can compute the same with the kernel and
 * compare the text. Checks here: the dot-product identity <J v, w> = <v, J^T w>, zero adjoint
 * at the free nodes, and bad input (a direct method, a short scratch, dim 4) returns its
 * status and leaves g untouched. Ends with "sensitivity_angle: every check held" (exit 0). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

#define S 6
#define N (S * S)

static double points[2 * N], w[2 * N], v[2 * N];
static float points32[2 * N], w32[2 * N], v32[2 * N];
static uint8_t fixed[N];
static uint32_t offsets[N + 1], targets[6 * N];

/* Adds the neighbour (i + di, j + dj) of node n when it exists. */
static void edge(size_t *k, long i, long j, long di, long dj) {
    if (i + di >= 0 && i + di < S && j + dj >= 0 && j + dj < S)
        targets[(*k)++] = (uint32_t)((i + di) + S * (j + dj));
}

static void build(void) {
    size_t k = 0;
    long i, j;
    offsets[0] = 0;
    for (j = 0; j < S; j++) {
        for (i = 0; i < S; i++) {
            size_t n = (size_t)(i + S * j);
            int b = i == 0 || j == 0 || i == S - 1 || j == S - 1;
            points[2 * n] = ((double)i + (b ? 0.0 : 0.06 * (double)((n * 7) % 5) - 0.12)) / (S - 1);
            points[2 * n + 1] = ((double)j + (b ? 0.0 : 0.05 * (double)((n * 3) % 5) - 0.1)) / (S - 1);
            fixed[n] = (uint8_t)b;
            w[2 * n] = sin(1.0 + (double)n);
            w[2 * n + 1] = cos(2.0 * (double)n);
            v[2 * n] = b ? 0.5 - 0.1 * (double)(n % 7) : 0.0;
            v[2 * n + 1] = b ? 0.05 * (double)(n % 5) : 0.0;
            /* Sorted: n-S-1, n-S, n-1, n+1, n+S, n+S+1. */
            edge(&k, i, j, -1, -1);
            edge(&k, i, j, 0, -1);
            edge(&k, i, j, -1, 0);
            edge(&k, i, j, 1, 0);
            edge(&k, i, j, 0, 1);
            edge(&k, i, j, 1, 1);
            offsets[n + 1] = (uint32_t)k;
        }
    }
    for (k = 0; k < 2 * N; k++) {
        points32[k] = (float)points[k];
        w32[k] = (float)w[k];
        v32[k] = (float)v[k];
    }
}

static double dot(const double *a, const double *b) {
    double s = 0.0;
    size_t i;
    for (i = 0; i < 2 * N; i++) s += a[i] * b[i];
    return s;
}

int main(void) {
    size_t e, len = 0, i;
    double *k, *s, g[2 * N], g0[2 * N], jv[2 * N];
    float *k32, *s32, g32[2 * N], jv32[2 * N];
    uint32_t index[N];
    dk_spring_angle_options o;
    dk_spring_solve_report r;
    build();
    e = offsets[N];
    dk_graph graph = {offsets, N + 1, targets, e};
    k = xmalloc(e * sizeof(double));
    k32 = xmalloc(e * sizeof(float));
    OK(dk_spring_batina_stiffness(&graph, points, 2 * N, 2, 1.0, k, e));
    OK(dk_spring_batina_stiffness_f32(&graph, points32, 2 * N, 2, 1.0f, k32, e));
    dk_spring_system sys = {graph, k, e, fixed, N};
    dk_spring_system_f32 sys32 = {graph, k32, e, fixed, N};
    hex64("points", points, 2 * N);
    hex64("w", w, 2 * N);
    hex64("v", v, 2 * N);
    OK(dk_sensitivity_angle_adjoint_scratch_len(N, 2, &len));
    s = xmalloc(len * sizeof(double));
    s32 = xmalloc(len * sizeof(float));

    OK(dk_spring_angle_options_default(&o));
    o.method = DK_ANGLE_CG;
    o.residual_tol = 1e-13;
    o.epsilon = 0.0;
    OK(dk_sensitivity_angle_adjoint(&sys, points, 2 * N, 2, &o, w, 2 * N, g, 2 * N, s, len,
                                    index, N, &r));
    CHECK(r.converged);
    for (i = 0; i < N; i++) CHECK(fixed[i] || (g[2 * i] == 0.0 && g[2 * i + 1] == 0.0));
    hex64("angle adjoint f64", g, 2 * N);
    printf("angle adjoint f64 report %zu %d\n", r.iterations, (int)r.converged);
    memcpy(jv, v, sizeof v);
    OK(dk_spring_solve_angle(&sys, points, 2 * N, 2, &o, jv, 2 * N, s, len, index, N, &r));
    CHECK(fabs(dot(jv, w) - dot(v, g)) <= 1e-11 * sqrt(dot(jv, jv) * dot(w, w)));
    hex64("angle tangent f64", jv, 2 * N);

    OK(dk_spring_angle_options_default_f32(&o));
    o.method = DK_ANGLE_CG;
    OK(dk_sensitivity_angle_adjoint_f32(&sys32, points32, 2 * N, 2, &o, w32, 2 * N, g32, 2 * N,
                                        s32, len, index, N, &r));
    hex32("angle adjoint f32", g32, 2 * N);
    printf("angle adjoint f32 report %zu %d\n", r.iterations, (int)r.converged);
    memcpy(jv32, v32, sizeof v32);
    OK(dk_spring_solve_angle_f32(&sys32, points32, 2 * N, 2, &o, jv32, 2 * N, s32, len, index, N,
                                 &r));
    hex32("angle tangent f32", jv32, 2 * N);

    /* Bad input: nothing written. */
    OK(dk_spring_angle_options_default(&o));
    o.method = DK_ANGLE_CG;
    memcpy(g0, g, sizeof g);
    EXPECT(dk_sensitivity_angle_adjoint(&sys, points, 2 * N, 2, &o, w, 2 * N, g, 2 * N, s,
                                        len - 1, index, N, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    o.method = DK_ANGLE_DIRECT_GAUSS_SEIDEL;
    EXPECT(dk_sensitivity_angle_adjoint(&sys, points, 2 * N, 2, &o, w, 2 * N, g, 2 * N, s, len,
                                        index, N, &r),
           DK_ERR_INVALID_PARAMETER);
    o.method = DK_ANGLE_CG;
    EXPECT(dk_sensitivity_angle_adjoint(&sys, points, 2 * N, 4, &o, w, 2 * N, g, 2 * N, s, len,
                                        index, N, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_sensitivity_angle_adjoint_scratch_len(N, 4, &len), DK_ERR_INVALID_PARAMETER);
    SAME(g, g0, sizeof g);
    free(k);
    free(k32);
    free(s);
    free(s32);
    printf("sensitivity_angle: every check held\n");
    return 0;
}

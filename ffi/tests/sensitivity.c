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
 * leaves the output untouched. Then the quaternion method with spring propagation
 * (dk_deform_spring_tangent and _adjoint, f64 0-based and f32 1-based, shape rotations of
 * the boundary loop): bits, the dot-product identity, bad input. Ends with
 * "sensitivity: every check held" (exit 0). */
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

/* The quaternion method with spring propagation (dk_deform_spring_tangent, _adjoint and the
 * f32 twins): the boundary loop turned by 0.2 rad about the centre, shifted and jittered,
 * rotations from its shape (segments along the loop), CG + Jacobi; f64 with 0-based nodes,
 * f32 with 1-based ones. */
static uint32_t seg_off[NB + 1], seg_nodes[2 * NB], seg_off1[NB + 1], seg_nodes1[2 * NB];
static uint8_t seg_kinds[NB];
static double dfm[2 * NB], dir[2 * NB];
static float dfm32[2 * NB], dir32[2 * NB];

/* The segments of the boundary loop (counter-clockwise, boundary-local numbering), the
 * deformed loop and the perturbation. */
static void loop(void) {
    uint32_t local[N], ring[NB];
    size_t i, k = 0;
    for (i = 0; i < NB; i++) local[boundary[i]] = (uint32_t)i;
    for (i = 0; i + 1 < S; i++) ring[k++] = (uint32_t)i;                  /* bottom */
    for (i = 0; i + 1 < S; i++) ring[k++] = (uint32_t)(S - 1 + S * i);    /* right */
    for (i = 0; i + 1 < S; i++) ring[k++] = (uint32_t)(N - 1 - i);        /* top */
    for (i = 0; i + 1 < S; i++) ring[k++] = (uint32_t)(S * (S - 1 - i));  /* left */
    for (i = 0; i < NB; i++) {
        double x = points[2 * boundary[i]] - 0.5, y = points[2 * boundary[i] + 1] - 0.5;
        seg_off[i] = (uint32_t)(2 * i);
        seg_off1[i] = (uint32_t)(2 * i + 1);
        seg_nodes[2 * i] = local[ring[i]];
        seg_nodes[2 * i + 1] = local[ring[(i + 1) % NB]];
        seg_nodes1[2 * i] = seg_nodes[2 * i] + 1;
        seg_nodes1[2 * i + 1] = seg_nodes[2 * i + 1] + 1;
        seg_kinds[i] = 3;
        dfm[2 * i] = 0.5 + cos(0.2) * x - sin(0.2) * y + 0.03 + 0.01 * sin(7.0 * (double)i);
        dfm[2 * i + 1] = 0.5 + sin(0.2) * x + cos(0.2) * y - 0.02 + 0.01 * cos(5.0 * (double)i);
        dir[2 * i] = sin(3.0 + (double)i);
        dir[2 * i + 1] = cos(1.0 + 2.0 * (double)i);
    }
    seg_off[NB] = 2 * NB;
    seg_off1[NB] = 2 * NB + 1;
    for (i = 0; i < 2 * NB; i++) {
        dfm32[i] = (float)dfm[i];
        dir32[i] = (float)dir[i];
    }
}

/* f64, 0-based: tangent, adjoint, the dot-product identity, bad input. */
static void quaternion_springs64(const dk_spring_system *sys, uint32_t *index, size_t ilen) {
    dk_boundary_motion m;
    dk_spring_solve_options o;
    dk_spring_solve_report r, r0;
    double jv[2 * N], g[2 * NB], g0[2 * NB], bad[2 * NB], a = 0.0, b = 0.0;
    size_t len = 0, need = 0, i;
    OK(dk_boundary_motion_default(&m));
    m.nodes = boundary;
    m.nodes_len = NB;
    m.deformed = dfm;
    m.deformed_len = 2 * NB;
    m.elements = (dk_cells){seg_off, NB + 1, seg_nodes, 2 * NB, seg_kinds, NB};
    OK(dk_spring_solve_options_default(&o));
    o.residual_tol = 1e-13;
    OK(dk_deform_spring_sensitivity_scratch_len(N, NB, 2, &o, &len));
    OK(dk_deform_spring_index_scratch_len(&m, N, &need));
    CHECK(need <= ilen);
    double *s = xmalloc(len * sizeof(double));
    OK(dk_deform_spring_tangent(points, 2 * N, 2, &m, sys, &o, dir, 2 * NB, s, len, index, ilen,
                                jv, 2 * N, &r));
    hex64("qspring tangent f64", jv, 2 * N);
    printf("qspring tangent f64 report %zu %d\n", r.iterations, (int)r.converged);
    OK(dk_deform_spring_adjoint(points, 2 * N, 2, &m, sys, &o, w, 2 * N, s, len, index, ilen, g,
                                2 * NB, &r));
    hex64("qspring adjoint f64", g, 2 * NB);
    printf("qspring adjoint f64 report %zu %d\n", r.iterations, (int)r.converged);
    a = dot(jv, w);
    for (i = 0; i < 2 * NB; i++) b += dir[i] * g[i];
    CHECK(fabs(a - b) <= 1e-11 * fabs(a));
    /* Bad input: nothing written. */
    memcpy(g0, g, sizeof g);
    r0 = r;
    memcpy(bad, dir, sizeof dir);
    bad[3] = NAN;
    EXPECT(dk_deform_spring_tangent(points, 2 * N, 2, &m, sys, &o, bad, 2 * NB, s, len, index,
                                    ilen, jv, 2 * N, &r),
           DK_ERR_NON_FINITE);
    EXPECT(dk_deform_spring_adjoint(points, 2 * N, 2, &m, sys, &o, w, 2 * N, s, len - 1, index,
                                    ilen, g, 2 * NB, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    o.method = DK_LINEAR_SOR;
    EXPECT(dk_deform_spring_adjoint(points, 2 * N, 2, &m, sys, &o, w, 2 * N, s, len, index, ilen,
                                    g, 2 * NB, &r),
           DK_ERR_INVALID_PARAMETER);
    SAME(g, g0, sizeof g);
    SAME(&r, &r0, sizeof r);
    free(s);
}

/* f32, 1-based: tangent and adjoint. */
static void quaternion_springs32(const dk_spring_system_f32 *sys, uint32_t *index, size_t ilen) {
    dk_boundary_motion_f32 m;
    dk_spring_solve_options o;
    dk_spring_solve_report r;
    float jv[2 * N], g[2 * NB];
    size_t len = 0, need = 0;
    OK(dk_boundary_motion_default_f32(&m));
    m.nodes = boundary1;
    m.nodes_len = NB;
    m.deformed = dfm32;
    m.deformed_len = 2 * NB;
    m.elements = (dk_cells){seg_off1, NB + 1, seg_nodes1, 2 * NB, seg_kinds, NB};
    m.index_base = 1;
    OK(dk_spring_solve_options_default_f32(&o));
    OK(dk_deform_spring_sensitivity_scratch_len(N, NB, 2, &o, &len));
    OK(dk_deform_spring_index_scratch_len_f32(&m, N, &need));
    CHECK(need <= ilen);
    float *s = xmalloc(len * sizeof(float));
    OK(dk_deform_spring_tangent_f32(points32, 2 * N, 2, &m, sys, &o, dir32, 2 * NB, s, len, index,
                                    ilen, jv, 2 * N, &r));
    hex32("qspring tangent f32", jv, 2 * N);
    printf("qspring tangent f32 report %zu %d\n", r.iterations, (int)r.converged);
    OK(dk_deform_spring_adjoint_f32(points32, 2 * N, 2, &m, sys, &o, w32, 2 * N, s, len, index,
                                    ilen, g, 2 * NB, &r));
    hex32("qspring adjoint f32", g, 2 * NB);
    printf("qspring adjoint f32 report %zu %d\n", r.iterations, (int)r.converged);
    free(s);
}

static void quaternion_springs(void) {
    size_t e = offsets[N], ilen = N + NB + 3 * NB + 1;
    dk_graph graph = {offsets, N + 1, targets, e};
    double *k = xmalloc(e * sizeof(double));
    float *k32 = xmalloc(e * sizeof(float));
    uint32_t *index = xmalloc(ilen * sizeof(uint32_t));
    loop();
    hex64("qdeformed", dfm, 2 * NB);
    hex64("qdirection", dir, 2 * NB);
    OK(dk_spring_batina_stiffness(&graph, points, 2 * N, 2, 1.0, k, e));
    OK(dk_spring_batina_stiffness_f32(&graph, points32, 2 * N, 2, 1.0f, k32, e));
    dk_spring_system sys = {graph, k, e, fixed, N};
    dk_spring_system_f32 sys32 = {graph, k32, e, fixed, N};
    quaternion_springs64(&sys, index, ilen);
    quaternion_springs32(&sys32, index, ilen);
    free(k);
    free(k32);
    free(index);
}

int main(void) {
    build();
    hex64("points", points, 2 * N);
    hex64("w", w, 2 * N);
    hex64("v", v, 2 * N);
    springs();
    idw();
    quaternion_springs();
    if (failures) return 1;
    printf("sensitivity: every check held\n");
    return 0;
}

/* The derivative of a plan's last step from C99 (issue 30): dk_plan_sensitivity_scratch_len,
 * dk_plan_tangent and dk_plan_adjoint (and the _f32 twins) on a 6 x 6 node jittered square,
 * its boundary loop turned by 0.2 rad, shifted and jittered, CG + Jacobi. After a cold step
 * the plan's derivatives must be, bit for bit, those of the stateless calls on the same mesh
 * and solver: the quaternion method's dk_deform_spring_tangent / dk_deform_spring_adjoint
 * (rotations from the loop's shape) and the linear springs' dk_sensitivity_spring_adjoint
 * (read at the boundary nodes); the linear springs' tangent satisfies the dot-product identity
 * <J v, w> = <v, J^T w> with their adjoint. Bad calls (no step yet, another motion, a short
 * scratch, a non-finite direction, a stationary solver's adjoint) return their status and
 * leave the output untouched. Prints "plan_sensitivity: every check held" (exit 0). */
#include <math.h>

#include "check.h"

#define S 6
#define N (S * S)
#define NB (4 * (S - 1))

static double points[2 * N], w[2 * N], dfm[2 * NB], dir[2 * NB];
static float points32[2 * N], w32[2 * N], dfm32[2 * NB], dir32[2 * NB];
static uint8_t fixed[N];
static uint32_t offsets[N + 1], targets[4 * N], boundary[NB];
static uint32_t seg_off[NB + 1], seg_nodes[2 * NB];
static uint8_t seg_kinds[NB];

/* The jittered grid, its 4-neighbour CSR graph, the boundary (node order), w. */
static void grid(void) {
    size_t i, j, k = 0, b = 0;
    for (j = 0; j < S; j++) {
        for (i = 0; i < S; i++) {
            size_t n = i + S * j;
            int edge = i == 0 || j == 0 || i == S - 1 || j == S - 1;
            double jx = edge ? 0.0 : 0.05 * (double)((n * 7) % 5) - 0.1;
            double jy = edge ? 0.0 : 0.04 * (double)((n * 3) % 5) - 0.08;
            points[2 * n] = ((double)i + jx) / (S - 1);
            points[2 * n + 1] = ((double)j + jy) / (S - 1);
            fixed[n] = (uint8_t)edge;
            if (edge) boundary[b++] = (uint32_t)n;
            w[2 * n] = sin(1.0 + (double)n);
            w[2 * n + 1] = cos(2.0 * (double)n);
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
    }
}

/* The loop's segments (counter-clockwise, boundary-local), the deformed loop, a perturbation. */
static void loop(void) {
    uint32_t local[N], ring[NB];
    size_t i, k = 0;
    for (i = 0; i < NB; i++) local[boundary[i]] = (uint32_t)i;
    for (i = 0; i + 1 < S; i++) ring[k++] = (uint32_t)i;
    for (i = 0; i + 1 < S; i++) ring[k++] = (uint32_t)(S - 1 + S * i);
    for (i = 0; i + 1 < S; i++) ring[k++] = (uint32_t)(N - 1 - i);
    for (i = 0; i + 1 < S; i++) ring[k++] = (uint32_t)(S * (S - 1 - i));
    for (i = 0; i < NB; i++) {
        double x = points[2 * boundary[i]] - 0.5, y = points[2 * boundary[i] + 1] - 0.5;
        seg_off[i] = (uint32_t)(2 * i);
        seg_nodes[2 * i] = local[ring[i]];
        seg_nodes[2 * i + 1] = local[ring[(i + 1) % NB]];
        seg_kinds[i] = 3;
        dfm[2 * i] = 0.5 + cos(0.2) * x - sin(0.2) * y + 0.03 + 0.01 * sin(7.0 * (double)i);
        dfm[2 * i + 1] = 0.5 + sin(0.2) * x + cos(0.2) * y - 0.02 + 0.01 * cos(5.0 * (double)i);
        dir[2 * i] = sin(3.0 + (double)i);
        dir[2 * i + 1] = cos(1.0 + 2.0 * (double)i);
    }
    seg_off[NB] = 2 * NB;
    for (i = 0; i < 2 * NB; i++) {
        dfm32[i] = (float)dfm[i];
        dir32[i] = (float)dir[i];
    }
}

static dk_plan_mesh mesh64(void) {
    return (dk_plan_mesh){.points = points,
                          .points_len = 2 * N,
                          .graph = {offsets, N + 1, targets, offsets[N]},
                          .boundary = boundary,
                          .boundary_len = NB,
                          .elements = {seg_off, NB + 1, seg_nodes, 2 * NB, seg_kinds, NB}};
}

/* A plan of `options` on the mesh in fresh pools (the caller frees them). */
static dk_plan_pools build64(const dk_plan_options *options) {
    dk_plan_mesh mesh = mesh64();
    dk_plan_sizes ws, ps;
    dk_plan_pools work, pools;
    dk_plan_info info;
    OK(dk_plan_work_sizes(&mesh, 2, options, &ws));
    work = (dk_plan_pools){xmalloc(ws.reals * sizeof(double)), ws.reals,
                           xmalloc(ws.indices * sizeof(uint32_t)), ws.indices,
                           xmalloc(ws.bytes), ws.bytes};
    OK(dk_plan_pool_sizes(&mesh, 2, options, &work, &ps));
    pools = (dk_plan_pools){xmalloc(ps.reals * sizeof(double)), ps.reals,
                            xmalloc(ps.indices * sizeof(uint32_t)), ps.indices,
                            xmalloc(ps.bytes), ps.bytes};
    OK(dk_plan_init(&mesh, 2, options, &work, &pools, &info));
    free(work.reals);
    free(work.indices);
    free(work.bytes);
    return pools;
}

static dk_plan_pools_f32 build32(const dk_plan_options *options) {
    dk_plan_mesh_f32 mesh = {.points = points32,
                             .points_len = 2 * N,
                             .graph = {offsets, N + 1, targets, offsets[N]},
                             .boundary = boundary,
                             .boundary_len = NB,
                             .elements = {seg_off, NB + 1, seg_nodes, 2 * NB, seg_kinds, NB}};
    dk_plan_sizes ws, ps;
    dk_plan_pools_f32 work, pools;
    dk_plan_info info;
    OK(dk_plan_work_sizes_f32(&mesh, 2, options, &ws));
    work = (dk_plan_pools_f32){xmalloc(ws.reals * sizeof(float)), ws.reals,
                               xmalloc(ws.indices * sizeof(uint32_t)), ws.indices,
                               xmalloc(ws.bytes), ws.bytes};
    OK(dk_plan_pool_sizes_f32(&mesh, 2, options, &work, &ps));
    pools = (dk_plan_pools_f32){xmalloc(ps.reals * sizeof(float)), ps.reals,
                                xmalloc(ps.indices * sizeof(uint32_t)), ps.indices,
                                xmalloc(ps.bytes), ps.bytes};
    OK(dk_plan_init_f32(&mesh, 2, options, &work, &pools, &info));
    free(work.reals);
    free(work.indices);
    free(work.bytes);
    return pools;
}

/* Plan options: `method`, CG + Jacobi with `linear`'s stopping rules. */
static dk_plan_options plan_options(uint32_t method, const dk_spring_solve_options *linear) {
    dk_plan_options o;
    OK(dk_plan_options_default(&o));
    o.method = method;
    o.solver = DK_PLAN_SOLVER_LINEAR;
    o.linear = *linear;
    return o;
}

/* The quaternion method in f64: bits against the stateless calls, then bad input. */
static void quaternion64(const dk_spring_system *sys, const dk_spring_solve_options *o) {
    dk_plan_options po = plan_options(DK_PLAN_QUATERNION, o);
    dk_plan_pools pools = build64(&po);
    dk_boundary_motion m;
    dk_plan_step_report step;
    dk_spring_solve_report r;
    static double out[2 * N], jv[2 * N], ejv[2 * N], g[2 * NB], eg[2 * NB], g0[2 * NB], bad[2 * NB];
    uint32_t index[N + 4 * NB + 1];
    size_t len = 0, elen = 0;
    OK(dk_plan_sensitivity_scratch_len(&pools, 2, &len));
    double *s = xmalloc(len * sizeof(double));
    /* No step yet. */
    memset(g, 0x5a, sizeof g);
    memcpy(g0, g, sizeof g);
    EXPECT(dk_plan_adjoint(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, w, 2 * N,
                           s, len, g, 2 * NB, &r),
           DK_ERR_INVALID_PARAMETER);
    SAME(g, g0, sizeof g);
    OK(dk_plan_step(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, DK_PLAN_COLD,
                    out, 2 * N, &step));
    OK(dk_plan_tangent(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, dir, 2 * NB,
                       s, len, jv, 2 * N, &r));
    CHECK(r.converged);
    OK(dk_plan_adjoint(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, w, 2 * N, s,
                       len, g, 2 * NB, &r));
    /* The stateless calls (they solve the deformation again first). */
    OK(dk_boundary_motion_default(&m));
    m.nodes = boundary;
    m.nodes_len = NB;
    m.deformed = dfm;
    m.deformed_len = 2 * NB;
    m.elements = (dk_cells){seg_off, NB + 1, seg_nodes, 2 * NB, seg_kinds, NB};
    OK(dk_deform_spring_sensitivity_scratch_len(N, NB, 2, o, &elen));
    CHECK(elen == len);
    double *es = xmalloc(elen * sizeof(double));
    OK(dk_deform_spring_tangent(points, 2 * N, 2, &m, sys, o, dir, 2 * NB, es, elen, index,
                                N + 4 * NB + 1, ejv, 2 * N, &r));
    OK(dk_deform_spring_adjoint(points, 2 * N, 2, &m, sys, o, w, 2 * N, es, elen, index,
                                N + 4 * NB + 1, eg, 2 * NB, &r));
    SAME(jv, ejv, sizeof jv);
    SAME(g, eg, sizeof g);
    /* Bad input: nothing written. */
    memcpy(g0, g, sizeof g);
    memcpy(bad, dfm, sizeof dfm);
    bad[5] += 1e-9;
    EXPECT(dk_plan_adjoint(&pools, 2, bad, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, w, 2 * N,
                           s, len, g, 2 * NB, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_plan_adjoint(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, w, 2 * N,
                           s, len - 1, g, 2 * NB, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    SAME(g, g0, sizeof g);
    memcpy(ejv, jv, sizeof jv);
    memcpy(bad, dir, sizeof dir);
    bad[3] = NAN;
    EXPECT(dk_plan_tangent(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, bad,
                           2 * NB, s, len, jv, 2 * N, &r),
           DK_ERR_NON_FINITE);
    EXPECT(dk_plan_tangent(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, dir,
                           2 * NB - 1, s, len, jv, 2 * N, &r),
           DK_ERR_LENGTH_MISMATCH);
    SAME(jv, ejv, sizeof jv);
    free(s);
    free(es);
    free(pools.reals);
    free(pools.indices);
    free(pools.bytes);
}

/* The linear springs in f64: the adjoint's bits against dk_sensitivity_spring_adjoint, the
 * dot-product identity with the tangent; a stationary solver has no adjoint. */
static void springs64(const dk_spring_system *sys, const dk_spring_solve_options *o) {
    dk_plan_options po = plan_options(DK_PLAN_SPRING, o);
    dk_plan_pools pools = build64(&po);
    dk_plan_step_report step;
    dk_spring_solve_report r;
    static double out[2 * N], jv[2 * N], g[2 * NB], eg[2 * N], g0[2 * NB];
    uint32_t index[N];
    size_t len = 0, elen = 0, i;
    double a = 0.0, b = 0.0;
    OK(dk_plan_sensitivity_scratch_len(&pools, 2, &len));
    double *s = xmalloc(len * sizeof(double));
    OK(dk_plan_step(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, DK_PLAN_COLD,
                    out, 2 * N, &step));
    OK(dk_plan_tangent(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, dir, 2 * NB,
                       s, len, jv, 2 * N, &r));
    OK(dk_plan_adjoint(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, w, 2 * N, s,
                       len, g, 2 * NB, &r));
    OK(dk_sensitivity_spring_adjoint_scratch_len(N, 2, o, &elen));
    double *es = xmalloc(elen * sizeof(double));
    OK(dk_sensitivity_spring_adjoint(sys, o, 2, w, 2 * N, eg, 2 * N, es, elen, index, N, &r));
    for (i = 0; i < NB; i++) SAME(&g[2 * i], &eg[2 * boundary[i]], 2 * sizeof(double));
    for (i = 0; i < 2 * N; i++) a += jv[i] * w[i];
    for (i = 0; i < 2 * NB; i++) b += dir[i] * g[i];
    CHECK(fabs(a - b) <= 1e-11 * (fabs(a) + fabs(b)));
    for (i = 0; i < NB; i++) CHECK(jv[2 * boundary[i]] == dir[2 * i]);
    free(pools.reals);
    free(pools.indices);
    free(pools.bytes);
    /* A stationary solver: a tangent, but no adjoint. */
    po.linear.method = DK_LINEAR_JACOBI;
    pools = build64(&po);
    OK(dk_plan_step(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, DK_PLAN_COLD,
                    out, 2 * N, &step));
    OK(dk_plan_sensitivity_scratch_len(&pools, 2, &elen));
    CHECK(elen <= len);
    OK(dk_plan_tangent(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, dir, 2 * NB,
                       s, len, jv, 2 * N, &r));
    memcpy(g0, g, sizeof g);
    EXPECT(dk_plan_adjoint(&pools, 2, dfm, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, w, 2 * N,
                           s, len, g, 2 * NB, &r),
           DK_ERR_INVALID_PARAMETER);
    SAME(g, g0, sizeof g);
    free(s);
    free(es);
    free(pools.reals);
    free(pools.indices);
    free(pools.bytes);
}

/* The quaternion method in f32: the twins' bits against the stateless f32 calls. */
static void quaternion32(const dk_spring_system_f32 *sys, const dk_spring_solve_options *o) {
    dk_plan_options po = plan_options(DK_PLAN_QUATERNION, o);
    dk_plan_pools_f32 pools = build32(&po);
    dk_boundary_motion_f32 m;
    dk_plan_step_report step;
    dk_spring_solve_report r;
    static float out[2 * N], jv[2 * N], ejv[2 * N], g[2 * NB], eg[2 * NB];
    uint32_t index[N + 4 * NB + 1];
    size_t len = 0;
    OK(dk_plan_sensitivity_scratch_len_f32(&pools, 2, &len));
    float *s = xmalloc(len * sizeof(float));
    OK(dk_plan_step_f32(&pools, 2, dfm32, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0,
                        DK_PLAN_COLD, out, 2 * N, &step));
    OK(dk_plan_tangent_f32(&pools, 2, dfm32, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, dir32,
                           2 * NB, s, len, jv, 2 * N, &r));
    OK(dk_plan_adjoint_f32(&pools, 2, dfm32, 2 * NB, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, w32,
                           2 * N, s, len, g, 2 * NB, &r));
    OK(dk_boundary_motion_default_f32(&m));
    m.nodes = boundary;
    m.nodes_len = NB;
    m.deformed = dfm32;
    m.deformed_len = 2 * NB;
    m.elements = (dk_cells){seg_off, NB + 1, seg_nodes, 2 * NB, seg_kinds, NB};
    OK(dk_deform_spring_tangent_f32(points32, 2 * N, 2, &m, sys, o, dir32, 2 * NB, s, len, index,
                                    N + 4 * NB + 1, ejv, 2 * N, &r));
    OK(dk_deform_spring_adjoint_f32(points32, 2 * N, 2, &m, sys, o, w32, 2 * N, s, len, index,
                                    N + 4 * NB + 1, eg, 2 * NB, &r));
    SAME(jv, ejv, sizeof jv);
    SAME(g, eg, sizeof g);
    free(s);
    free(pools.reals);
    free(pools.indices);
    free(pools.bytes);
}

int main(void) {
    size_t e;
    dk_spring_solve_options o, o32;
    grid();
    loop();
    e = offsets[N];
    dk_graph graph = {offsets, N + 1, targets, e};
    double *k = xmalloc(e * sizeof(double));
    float *k32 = xmalloc(e * sizeof(float));
    OK(dk_spring_batina_stiffness(&graph, points, 2 * N, 2, 1.0, k, e));
    OK(dk_spring_batina_stiffness_f32(&graph, points32, 2 * N, 2, 1.0f, k32, e));
    dk_spring_system sys = {graph, k, e, fixed, N};
    dk_spring_system_f32 sys32 = {graph, k32, e, fixed, N};
    OK(dk_spring_solve_options_default(&o));
    o.residual_tol = 1e-13;
    OK(dk_spring_solve_options_default_f32(&o32));
    quaternion64(&sys, &o);
    springs64(&sys, &o);
    quaternion32(&sys32, &o32);
    free(k);
    free(k32);
    if (failures) return 1;
    printf("plan_sensitivity: every check held\n");
    return 0;
}

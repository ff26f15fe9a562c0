/* Renumbered plans from C99 (dk_plan_work_sizes_ordered, dk_plan_pool_sizes_ordered,
 * dk_plan_init_ordered) on a 13 x 9 triangulated grid numbered at random (an LCG shuffle),
 * the spring method (multigrid) and the quaternion method (CG, a rigid rotation).
 *
 * Checks here: a plan renumbered by RCM writes, cold and warm, bit for bit what a plain plan
 * (dk_plan_init) gives on the mesh this program renumbers with dk_order_rcm,
 * dk_order_permute, dk_order_permute_graph and dk_order_renumber, put back with the
 * permutation inverted; its pools are 2 N indices larger; an unknown `renumber` is
 * DK_ERR_INVALID_PARAMETER with the outputs untouched; the _f32 twins give the same identity. Prints the mesh, the motion and each
 * method's final mesh in hex, so host-tests/tests/ffi/c_abi_plan.rs can compare with the
 * Rust plan. Ends with "plan_order: every check held" (exit 0). */
#include "check.h"

#define NX 13
#define NY 9
#define N (NX * NY)
#define EDGES ((NX - 1) * NY + NX * (NY - 1) + (NX - 1) * (NY - 1))
#define B (2 * (NX + NY) - 4)

static uint32_t edges[2 * EDGES], offsets[N + 1], targets[2 * EDGES], boundary[B];
static size_t used;
static double points[2 * N], deformed[2 * B];

/* The grid, numbered at random; the perimeter is the boundary, the top row moved up. */
static void build(void) {
    static uint32_t label[N];
    size_t i, j, e = 0, b = 0;
    lcg_shuffle(label, N, 777);
    for (j = 0; j < NY; j++)
        for (i = 0; i < NX; i++) {
            uint32_t n = label[i + NX * j];
            points[2 * n] = 0.25 * (double)i + 0.01 * (double)(j * j);
            points[2 * n + 1] = 0.5 * (double)j;
            if (i + 1 < NX) { edges[e++] = n; edges[e++] = label[i + 1 + NX * j]; }
            if (j + 1 < NY) { edges[e++] = n; edges[e++] = label[i + NX * (j + 1)]; }
            if (i + 1 < NX && j + 1 < NY) { edges[e++] = n; edges[e++] = label[i + 1 + NX * (j + 1)]; }
            if (i == 0 || j == 0 || i + 1 == NX || j + 1 == NY) {
                boundary[b] = n;
                deformed[2 * b] = points[2 * n] + (j + 1 == NY ? 0.05 * (double)i : 0.0);
                deformed[2 * b + 1] = points[2 * n + 1] + (j + 1 == NY ? 0.4 : 0.0);
                b++;
            }
        }
    CHECK(b == B);
    OK(dk_graph_from_edges(N, edges, 2 * EDGES, 0, NULL, 0, offsets, N + 1, targets, 2 * EDGES, &used));
}

static void ints(const char *name, const uint32_t *v, size_t n) {
    size_t i;
    printf("%s", name);
    for (i = 0; i < n; i++) printf(" %u", (unsigned)v[i]);
    printf("\n");
}

/* Zeroed pools of these sizes. */
static dk_plan_pools alloc_pools(dk_plan_sizes s) {
    dk_plan_pools p = {xmalloc(s.reals * sizeof(double)), s.reals,
                       xmalloc(s.indices * sizeof(uint32_t)), s.indices, xmalloc(s.bytes), s.bytes};
    memset(p.reals, 0, s.reals * sizeof(double));
    memset(p.indices, 0, s.indices * sizeof(uint32_t));
    memset(p.bytes, 0, s.bytes);
    return p;
}

static void release(dk_plan_pools *p) {
    free(p->reals);
    free(p->indices);
    free(p->bytes);
}

/* A plan of `mesh` in fresh pools, renumbered by `renumber`; its pool sizes in `sizes`. */
static dk_plan_pools plan(const dk_plan_mesh *mesh, const dk_plan_options *o, uint32_t renumber,
                          dk_plan_sizes *sizes) {
    dk_plan_sizes ws;
    dk_plan_pools work, pools;
    dk_plan_info info;
    OK(dk_plan_work_sizes_ordered(mesh, 2, o, renumber, &ws));
    work = alloc_pools(ws);
    OK(dk_plan_pool_sizes_ordered(mesh, 2, o, renumber, &work, sizes));
    pools = alloc_pools(*sizes);
    OK(dk_plan_init_ordered(mesh, 2, o, renumber, &work, &pools, &info));
    CHECK(info.nodes == N && info.boundary == B);
    release(&work);
    return pools;
}

/* The RCM plan against the plain plan on the mesh renumbered here, cold then warm. */
static void against_renumbered(uint32_t method, const char *name) {
    static uint32_t order[N], inverse[N], r_offsets[N + 1], r_targets[2 * EDGES], r_boundary[B];
    static double r_points[2 * N], out[2 * N], r_out[2 * N], back[2 * N];
    const double rotation[4] = {0.9987502603949663, 0.0, 0.0, 0.04997916927067833};
    dk_graph graph = {offsets, N + 1, targets, used};
    dk_plan_mesh mesh = {points, 2 * N, {offsets, N + 1, targets, used}, boundary, B, {0}, NULL, 0};
    dk_permutation perm = {order, N, inverse, N}, undo = {inverse, N, order, N};
    dk_plan_options o;
    dk_plan_sizes so, sr;
    dk_plan_pools po, pr;
    dk_plan_step_report ro, rr;
    int s;
    OK(dk_plan_options_default(&o));
    o.method = method;
    if (method == DK_PLAN_QUATERNION) o.solver = DK_PLAN_SOLVER_LINEAR;
    po = plan(&mesh, &o, DK_PLAN_ORDER_RCM, &so);
    OK(dk_order_rcm(&graph, order, N, inverse, N));
    OK(dk_order_permute(&perm, 2, points, 2 * N, r_points, 2 * N));
    OK(dk_order_permute_graph(&perm, &graph, r_offsets, N + 1, r_targets, used, NULL, 0));
    memcpy(r_boundary, boundary, sizeof boundary);
    OK(dk_order_renumber(&perm, 0, r_boundary, B));
    mesh = (dk_plan_mesh){r_points, 2 * N, {r_offsets, N + 1, r_targets, used}, r_boundary, B, {0}, NULL, 0};
    pr = plan(&mesh, &o, DK_PLAN_ORDER_NONE, &sr);
    CHECK(so.indices == sr.indices + 2 * N && so.reals == sr.reals && so.bytes == sr.bytes);
    for (s = 0; s < 2; s++) {
        uint32_t start = s == 0 ? DK_PLAN_COLD : DK_PLAN_WARM;
        OK(dk_plan_step(&po, 2, deformed, 2 * B, DK_ROTATIONS_RIGID, rotation, 4, NULL, 0, start,
                        out, 2 * N, &ro));
        OK(dk_plan_step(&pr, 2, deformed, 2 * B, DK_ROTATIONS_RIGID, rotation, 4, NULL, 0, start,
                        r_out, 2 * N, &rr));
        OK(dk_order_permute(&undo, 2, r_out, 2 * N, back, 2 * N));
        SAME(out, back, sizeof out);
        CHECK(ro.iterations == rr.iterations && ro.warm == rr.warm && ro.converged);
    }
    hex64(name, out, 2 * N);
    release(&po);
    release(&pr);
}

/* An unknown `renumber` is refused by the three calls; their outputs stay as they were. */
static void bad_renumber(void) {
    dk_plan_mesh mesh = {points, 2 * N, {offsets, N + 1, targets, used}, boundary, B, {0}, NULL, 0};
    dk_plan_options o;
    dk_plan_sizes ws, ps, before;
    dk_plan_pools work, pools;
    dk_plan_info info, info_before;
    OK(dk_plan_options_default(&o));
    OK(dk_plan_work_sizes_ordered(&mesh, 2, &o, DK_PLAN_ORDER_HILBERT, &ws));
    work = alloc_pools(ws);
    OK(dk_plan_pool_sizes_ordered(&mesh, 2, &o, DK_PLAN_ORDER_HILBERT, &work, &ps));
    pools = alloc_pools(ps);
    POISON(before);
    ws = before;
    EXPECT(dk_plan_work_sizes_ordered(&mesh, 2, &o, 3, &ws), DK_ERR_INVALID_PARAMETER);
    SAME(&ws, &before, sizeof ws);
    EXPECT(dk_plan_pool_sizes_ordered(&mesh, 2, &o, 3, &work, &ws), DK_ERR_INVALID_PARAMETER);
    SAME(&ws, &before, sizeof ws);
    POISON(info_before);
    info = info_before;
    EXPECT(dk_plan_init_ordered(&mesh, 2, &o, 3, &work, &pools, &info), DK_ERR_INVALID_PARAMETER);
    SAME(&info, &info_before, sizeof info);
    EXPECT(dk_plan_open(&pools, 2, &info), DK_ERR_BAD_PLAN);
    OK(dk_plan_init_ordered(&mesh, 2, &o, DK_PLAN_ORDER_HILBERT, &work, &pools, &info));
    OK(dk_plan_open(&pools, 2, &info));
    release(&work);
    release(&pools);
}

/* Zeroed f32 pools of these sizes. */
static dk_plan_pools_f32 alloc_pools_f32(dk_plan_sizes s) {
    dk_plan_pools_f32 p = {xmalloc(s.reals * sizeof(float)), s.reals,
                           xmalloc(s.indices * sizeof(uint32_t)), s.indices, xmalloc(s.bytes),
                           s.bytes};
    memset(p.reals, 0, s.reals * sizeof(float));
    memset(p.indices, 0, s.indices * sizeof(uint32_t));
    memset(p.bytes, 0, s.bytes);
    return p;
}

/* An f32 plan of `mesh` in fresh pools, renumbered by `renumber`. */
static dk_plan_pools_f32 plan_f32(const dk_plan_mesh_f32 *mesh, const dk_plan_options *o,
                                  uint32_t renumber) {
    dk_plan_sizes ws, ps;
    dk_plan_pools_f32 work, pools;
    dk_plan_info info;
    OK(dk_plan_work_sizes_ordered_f32(mesh, 2, o, renumber, &ws));
    work = alloc_pools_f32(ws);
    OK(dk_plan_pool_sizes_ordered_f32(mesh, 2, o, renumber, &work, &ps));
    pools = alloc_pools_f32(ps);
    OK(dk_plan_init_ordered_f32(mesh, 2, o, renumber, &work, &pools, &info));
    CHECK(info.nodes == N && info.boundary == B);
    free(work.reals);
    free(work.indices);
    free(work.bytes);
    return pools;
}

/* The f32 twins: an RCM spring plan against the plain f32 plan on the renumbered mesh. */
static void against_renumbered_f32(void) {
    static uint32_t order[N], inverse[N], r_offsets[N + 1], r_targets[2 * EDGES], r_boundary[B];
    static float p32[2 * N], d32[2 * B], r_points[2 * N], out[2 * N], r_out[2 * N], back[2 * N];
    dk_graph graph = {offsets, N + 1, targets, used};
    dk_permutation perm = {order, N, inverse, N}, undo = {inverse, N, order, N};
    dk_plan_options o;
    dk_plan_pools_f32 po, pr;
    dk_plan_step_report ro, rr;
    size_t i;
    for (i = 0; i < 2 * N; i++) p32[i] = (float)points[i];
    for (i = 0; i < 2 * B; i++) d32[i] = (float)deformed[i];
    OK(dk_plan_options_default_f32(&o));
    o.method = DK_PLAN_SPRING;
    {
        dk_plan_mesh_f32 mesh = {p32, 2 * N, {offsets, N + 1, targets, used}, boundary, B, {0},
                                 NULL, 0};
        po = plan_f32(&mesh, &o, DK_PLAN_ORDER_RCM);
    }
    OK(dk_order_rcm(&graph, order, N, inverse, N));
    OK(dk_order_permute_f32(&perm, 2, p32, 2 * N, r_points, 2 * N));
    OK(dk_order_permute_graph(&perm, &graph, r_offsets, N + 1, r_targets, used, NULL, 0));
    memcpy(r_boundary, boundary, sizeof boundary);
    OK(dk_order_renumber(&perm, 0, r_boundary, B));
    {
        dk_plan_mesh_f32 mesh = {r_points, 2 * N, {r_offsets, N + 1, r_targets, used}, r_boundary,
                                 B, {0}, NULL, 0};
        pr = plan_f32(&mesh, &o, DK_PLAN_ORDER_NONE);
    }
    OK(dk_plan_step_f32(&po, 2, d32, 2 * B, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, DK_PLAN_COLD,
                        out, 2 * N, &ro));
    OK(dk_plan_step_f32(&pr, 2, d32, 2 * B, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, DK_PLAN_COLD,
                        r_out, 2 * N, &rr));
    OK(dk_order_permute_f32(&undo, 2, r_out, 2 * N, back, 2 * N));
    SAME(out, back, sizeof out);
    CHECK(ro.iterations == rr.iterations && ro.converged);
    free(po.reals); free(po.indices); free(po.bytes);
    free(pr.reals); free(pr.indices); free(pr.bytes);
}

int main(void) {
    build();
    hex64("points", points, 2 * N);
    ints("offsets", offsets, N + 1);
    ints("targets", targets, used);
    ints("boundary", boundary, B);
    hex64("deformed", deformed, 2 * B);
    against_renumbered(DK_PLAN_SPRING, "spring");
    against_renumbered(DK_PLAN_QUATERNION, "quaternion");
    against_renumbered_f32();
    bad_renumber();
    if (failures) return 1;
    printf("plan_order: every check held\n");
    return 0;
}

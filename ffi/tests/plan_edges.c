/* Prepared plans at the edges of their parameters (issue 26 item 7): a one-level multigrid
 * hierarchy (max_levels 1, or a mesh with one free node) is built and stepped like the
 * stateless multigrid solve; dk_plan_work_sizes refuses what dk_plan_pool_sizes refuses
 * (points NULL, empty or too long, a short stiffness) with the same status; the spring
 * method ignores rotation_source, as documented. Prints "plan_edges: every check held". */
#include "check.h"

#define NX 5
#define N (NX * NX)
#define B (4 * (NX - 1))
#define E_MAX (8 * N)

static double points[2 * N], deformed[2 * B];
static uint32_t offsets[N + 1], targets[E_MAX], boundary[N];
static size_t edges;

/* An NX x NX grid of quads, its edge graph, the perimeter as boundary (top row up by 0.5). */
static void grid(void) {
    static uint32_t co[(NX - 1) * (NX - 1) + 1], cn[4 * (NX - 1) * (NX - 1)];
    static uint8_t ck[(NX - 1) * (NX - 1)];
    size_t targets_len;
    int i, j, c = 0, b = 0;
    dk_cells cells;
    for (j = 0; j < NX; j++)
        for (i = 0; i < NX; i++) {
            points[2 * (j * NX + i)] = (double)i;
            points[2 * (j * NX + i) + 1] = (double)j;
        }
    for (j = 0; j + 1 < NX; j++)
        for (i = 0; i + 1 < NX; i++, c++) {
            co[c] = (uint32_t)(4 * c);
            cn[4 * c] = (uint32_t)(j * NX + i);
            cn[4 * c + 1] = (uint32_t)(j * NX + i + 1);
            cn[4 * c + 2] = (uint32_t)((j + 1) * NX + i + 1);
            cn[4 * c + 3] = (uint32_t)((j + 1) * NX + i);
            ck[c] = 9;
        }
    co[c] = (uint32_t)(4 * c);
    cells = (dk_cells){co, (size_t)c + 1, cn, 4 * (size_t)c, ck, (size_t)c};
    OK(dk_graph_from_cells_len(N, &cells, 0, NULL, 0, true, &targets_len));
    CHECK(targets_len <= E_MAX);
    OK(dk_graph_from_cells(N, &cells, 0, NULL, 0, true, offsets, N + 1, targets, E_MAX,
                           &edges));
    for (j = 0; j < NX; j++)
        for (i = 0; i < NX; i++)
            if (i == 0 || j == 0 || i == NX - 1 || j == NX - 1) {
                int n = j * NX + i;
                boundary[b] = (uint32_t)n;
                deformed[2 * b] = points[2 * n];
                deformed[2 * b + 1] = points[2 * n + 1] + (j == NX - 1 ? 0.5 : 0.0);
                b++;
            }
}

static dk_plan_mesh mesh_of(size_t boundary_len) {
    return (dk_plan_mesh){.points = points,
                          .points_len = 2 * N,
                          .graph = {offsets, N + 1, targets, edges},
                          .boundary = boundary,
                          .boundary_len = boundary_len};
}

/* Builds a plan in fresh pools (freed by the caller through `pools->reals` etc.); returns the
 * status of dk_plan_init (after the size queries, which must succeed). */
static dk_status build(const dk_plan_mesh *mesh, const dk_plan_options *options,
                       dk_plan_pools *pools, dk_plan_info *info) {
    dk_plan_sizes ws, ps;
    dk_plan_pools work;
    dk_status s;
    OK(dk_plan_work_sizes(mesh, 2, options, &ws));
    work = (dk_plan_pools){xmalloc(ws.reals * sizeof(double)), ws.reals,
                           xmalloc(ws.indices * sizeof(uint32_t)), ws.indices,
                           xmalloc(ws.bytes), ws.bytes};
    OK(dk_plan_pool_sizes(mesh, 2, options, &work, &ps));
    *pools = (dk_plan_pools){xmalloc(ps.reals * sizeof(double)), ps.reals,
                             xmalloc(ps.indices * sizeof(uint32_t)), ps.indices,
                             xmalloc(ps.bytes), ps.bytes};
    s = dk_plan_init(mesh, 2, options, &work, pools, info);
    free(work.reals);
    free(work.indices);
    free(work.bytes);
    return s;
}

static void release(dk_plan_pools *p) {
    free(p->reals);
    free(p->indices);
    free(p->bytes);
}

/* One spring step of `pools` with `rotation_source`; the deformed mesh into `out`. */
static dk_status step(const dk_plan_pools *pools, uint32_t rotation_source, size_t b,
                      double *out, dk_plan_step_report *report) {
    return dk_plan_step(pools, 2, deformed, 2 * b, rotation_source, NULL, 0, NULL, 0,
                        DK_PLAN_COLD, out, 2 * N, report);
}

/* One multigrid level: the plan builds, reports one level, steps and converges. */
static void one_level(void) {
    static double out[2 * N];
    dk_plan_options options;
    dk_plan_pools pools;
    dk_plan_info info;
    dk_plan_step_report report;
    dk_plan_mesh mesh = mesh_of(B);
    OK(dk_plan_options_default(&options));
    options.method = DK_PLAN_SPRING;
    options.amg.max_levels = 1;
    OK(build(&mesh, &options, &pools, &info));
    CHECK(info.amg_levels == 1);
    OK(step(&pools, DK_ROTATIONS_SHAPE, B, out, &report));
    CHECK(report.converged);
    CHECK(out[2 * (2 * NX + 2) + 1] > 2.0 && out[2 * (2 * NX + 2) + 1] < 2.5);
    release(&pools);
}

/* Every node but the centre held: one free node, a hierarchy of one level. */
static void one_free_node(void) {
    static double out[2 * N];
    static double moved[2 * N];
    dk_plan_options options;
    dk_plan_pools pools;
    dk_plan_info info;
    dk_plan_step_report report;
    dk_plan_mesh mesh;
    uint32_t centre = (NX / 2) * NX + NX / 2;
    size_t b = 0, k;
    for (k = 0; k < N; k++)
        if (k != centre) boundary[b++] = (uint32_t)k;
    for (k = 0; k < b; k++) {
        moved[2 * k] = points[2 * boundary[k]];
        moved[2 * k + 1] = points[2 * boundary[k] + 1] * 1.25;
    }
    mesh = mesh_of(b);
    OK(dk_plan_options_default(&options));
    options.method = DK_PLAN_SPRING;
    OK(build(&mesh, &options, &pools, &info));
    CHECK(info.amg_levels == 1);
    OK(dk_plan_step(&pools, 2, moved, 2 * b, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0,
                    DK_PLAN_COLD, out, 2 * N, &report));
    CHECK(report.converged);
    /* The centre of a uniformly stretched square stays at the centre of the stretch. */
    CHECK(out[2 * centre] == points[2 * centre]);
    CHECK(out[2 * centre + 1] > 2.49 && out[2 * centre + 1] < 2.51);
    release(&pools);
    grid(); /* restore the perimeter boundary */
}

/* dk_plan_work_sizes refuses what dk_plan_pool_sizes refuses, with the same status; the sizes
 * are not written. */
static void work_sizes_validate(void) {
    static double k[E_MAX];
    dk_plan_options options;
    dk_plan_sizes sizes, untouched, ws;
    dk_plan_pools work;
    dk_plan_mesh good = mesh_of(B), bad;
    int c;
    OK(dk_plan_options_default(&options));
    OK(dk_plan_work_sizes(&good, 2, &options, &ws));
    work = (dk_plan_pools){xmalloc(ws.reals * sizeof(double)), ws.reals,
                           xmalloc(ws.indices * sizeof(uint32_t)), ws.indices,
                           xmalloc(ws.bytes), ws.bytes};
    OK(dk_spring_batina_stiffness(&good.graph, points, 2 * N, 2, 1.0, k, edges));
    for (c = 0; c < 5; c++) {
        dk_status expected, got;
        bad = good;
        switch (c) {
        case 0: bad.points = NULL; break;                           /* NULL, length 2N */
        case 1: bad.points = NULL; bad.points_len = 0; break;       /* NULL, length 0 */
        case 2: bad.points_len = 0; break;                          /* empty */
        case 3: bad.points_len = 2 * N - 2; break;                  /* one node short */
        case 4: bad.stiffness = k; bad.stiffness_len = edges - 1; break; /* short stiffness */
        }
        expected = dk_plan_pool_sizes(&bad, 2, &options, &work, &sizes);
        CHECK(expected != DK_OK);
        POISON(sizes);
        memcpy(&untouched, &sizes, sizeof sizes);
        got = dk_plan_work_sizes(&bad, 2, &options, &sizes);
        if (got != expected)
            printf("FAIL case %d: dk_plan_work_sizes gave %d, dk_plan_pool_sizes %d\n", c,
                   (int)got, (int)expected);
        failures += got != expected;
        SAME(&sizes, &untouched, sizeof sizes);
    }
    /* A length beyond what any mesh can have (the pointer is never read that far). */
    bad = good;
    bad.points_len = SIZE_MAX - 1;
    EXPECT(dk_plan_work_sizes(&bad, 2, &options, &sizes), DK_ERR_LENGTH_MISMATCH);
    free(work.reals);
    free(work.indices);
    free(work.bytes);
}

/* The spring method ignores rotation_source: any value gives the same bits. */
static void spring_ignores_rotation_source(void) {
    static double a[2 * N], b[2 * N];
    dk_plan_options options;
    dk_plan_pools pools;
    dk_plan_info info;
    dk_plan_step_report report;
    dk_plan_mesh mesh = mesh_of(B);
    OK(dk_plan_options_default(&options));
    options.method = DK_PLAN_SPRING;
    OK(build(&mesh, &options, &pools, &info));
    OK(step(&pools, DK_ROTATIONS_SHAPE, B, a, &report));
    OK(step(&pools, 77, B, b, &report));
    SAME(a, b, sizeof a);
    release(&pools);
    /* The quaternion method still refuses an unknown source. */
    options.method = DK_PLAN_QUATERNION;
    OK(build(&mesh, &options, &pools, &info));
    EXPECT(step(&pools, 77, B, b, &report), DK_ERR_INVALID_PARAMETER);
    release(&pools);
}

int main(void) {
    grid();
    one_level();
    one_free_node();
    work_sizes_validate();
    spring_ignores_rotation_source();
    if (failures) return EXIT_FAILURE;
    printf("plan_edges: every check held\n");
    return EXIT_SUCCESS;
}

/* The elasticity multigrid and sliding solves from C99: dk_elasticity_amg_pool_sizes,
 * dk_elasticity_deform_amg (and _f32), dk_elasticity_sliding_scratch_len,
 * dk_elasticity_deform_sliding (and _f32) and dk_elasticity_deform_sliding_amg (and _f32) on
 * the 6 x 6 node square of elasticity.c (quads and triangles, interior jittered) in 2
 * increments with inverse-volume moduli and a multigrid of at most 8 coarse nodes: double
 * with 0-based cells, float with 1-based ones. The plain runs fix the whole boundary (moved
 * by the linear field (0.1 y, -0.05 x)); the sliding runs let the bottom edge's inner nodes
 * slide along y = 0 (kind 2, normal (0, 1)) and fix the rest of the boundary.
 *
 * Prints the points, the displacement and the bits and reports of every run, so
 * host-tests/tests/ffi/c_abi_elasticity_solvers.rs can compute the same with the kernel and
 * compare the text. Checks here: the fixed nodes end at points + displacement, the sliding
 * nodes stay on y = 0, and bad input (short pools and scratch, sliding 2, dim 4, an unknown
 * smoother, a fixed mask that disagrees with the constraints) returns its status and leaves
 * the points untouched. Ends with "elasticity solvers: every check held" (exit 0), or prints
 * each failed check (exit 1). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

#define S 6
#define N (S * S)
#define NQ ((S - 1) * (S - 1))

static uint32_t coffs[2 * NQ + 1], coffs1[2 * NQ + 1], cnodes[6 * NQ], cnodes1[6 * NQ];
static uint8_t ckinds[2 * NQ];
static size_t ncells;
static double points[2 * N], disp[2 * N], normals[2 * N];
static float disp32[2 * N], normals32[2 * N];
static uint8_t fixed[N], sfixed[N], kinds[N];

/* Quads where (i + j) is odd, two triangles elsewhere; interior nodes jittered; the bottom
 * edge's inner nodes slide in the sliding runs. */
static void build(void) {
    size_t i, j, k = 0;
    for (j = 0; j < S; j++) {
        for (i = 0; i < S; i++) {
            size_t n = i + S * j;
            int edge = i == 0 || j == 0 || i == S - 1 || j == S - 1;
            int slides = j == 0 && i > 0 && i < S - 1;
            double jx = edge ? 0.0 : 0.05 * (double)((n * 7) % 5) - 0.1;
            double jy = edge ? 0.0 : 0.04 * (double)((n * 3) % 5) - 0.08;
            points[2 * n] = ((double)i + jx) / (S - 1);
            points[2 * n + 1] = ((double)j + jy) / (S - 1);
            fixed[n] = (uint8_t)edge;
            sfixed[n] = (uint8_t)(edge && !slides);
            kinds[n] = (uint8_t)(slides ? 2 : sfixed[n]);
            normals[2 * n + 1] = 1.0;
            normals32[2 * n + 1] = 1.0f;
            disp[2 * n] = edge ? 0.1 * points[2 * n + 1] : 0.0;
            disp[2 * n + 1] = edge ? -0.05 * points[2 * n] : 0.0;
            disp32[2 * n] = (float)disp[2 * n];
            disp32[2 * n + 1] = (float)disp[2 * n + 1];
        }
    }
    coffs[0] = 0;
    for (j = 0; j + 1 < S; j++) {
        for (i = 0; i + 1 < S; i++) {
            uint32_t a = (uint32_t)(i + S * j), q[4] = {a, a + 1, a + 1 + S, a + S};
            if ((i + j) % 2) {
                memcpy(cnodes + k, q, sizeof q);
                k += 4;
                ckinds[ncells++] = 9;
                coffs[ncells] = (uint32_t)k;
            } else {
                uint32_t t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
                size_t h;
                for (h = 0; h < 2; h++) {
                    memcpy(cnodes + k, t + 3 * h, 3 * sizeof *t);
                    k += 3;
                    ckinds[ncells++] = 5;
                    coffs[ncells] = (uint32_t)k;
                }
            }
        }
    }
    for (i = 0; i < k; i++) cnodes1[i] = cnodes[i] + 1;
    for (i = 0; i <= ncells; i++) coffs1[i] = coffs[i] + 1;
}

static unsigned long long dbits(double x) {
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return (unsigned long long)b;
}

static void report(const char *tag, const dk_elasticity_report *r) {
    printf("%s report %zu %zu %zu %016llX %d\n", tag, r->steps, r->iterations,
           r->max_step_iterations, dbits(r->residual), (int)r->converged);
}

static dk_cells cells, cells1;
static dk_graph graph;
static uint32_t *index_scratch;
static size_t iscr_len;

/* The fixed nodes (of `mask`) end at points + displacement; in the sliding runs (`mask` is
 * sfixed) the sliding nodes stay on y = 0. */
static void check_ends(const double *moved, const uint8_t *mask) {
    size_t k;
    for (k = 0; k < N; k++) {
        if (mask[k]) {
            CHECK(moved[2 * k] == points[2 * k] + disp[2 * k]);
            CHECK(moved[2 * k + 1] == points[2 * k + 1] + disp[2 * k + 1]);
        }
        if (mask == sfixed && kinds[k] == 2) CHECK(moved[2 * k + 1] == 0.0);
    }
}

int main(void) {
    uint32_t offsets[N + 1], *targets, *work, *indices;
    size_t tlen, used, wlen, slen, k, rlen, ilen;
    dk_amg_options amg;
    dk_plan_sizes sizes, ssizes;
    dk_plan_pools pools;
    dk_plan_pools_f32 pools32;
    dk_constraints con;
    dk_constraints_f32 con32;
    dk_elasticity_options o, o32;
    dk_elasticity_report r;
    double *weights, *reals, *scratch, moved[2 * N], keep[2 * N];
    float *reals32, *scratch32, moved32[2 * N];
    build();
    cells.offsets = coffs;
    cells.offsets_len = ncells + 1;
    cells.nodes = cnodes;
    cells.nodes_len = coffs[ncells];
    cells.kinds = ckinds;
    cells.kinds_len = ncells;
    cells1 = cells;
    cells1.nodes = cnodes1;
    cells1.offsets = coffs1;
    iscr_len = ncells + 1 + coffs[ncells];
    index_scratch = xmalloc(iscr_len * sizeof *index_scratch);
    OK(dk_elasticity_graph_len(N, &cells, 0, NULL, 0, &tlen));
    targets = xmalloc(tlen * sizeof *targets);
    OK(dk_elasticity_graph(N, &cells, 0, NULL, 0, offsets, N + 1, targets, tlen, &used));
    graph.offsets = offsets;
    graph.offsets_len = N + 1;
    graph.targets = targets;
    graph.targets_len = used;
    con.kinds = kinds;
    con.kinds_len = N;
    con.directions = normals;
    con.directions_len = 2 * N;
    con32.kinds = kinds;
    con32.kinds_len = N;
    con32.directions = normals32;
    con32.directions_len = 2 * N;
    hex64("points", points, 2 * N);
    hex64("disp", disp, 2 * N);

    OK(dk_amg_options_default(&amg));
    amg.max_coarse = 8;
    OK(dk_spring_amg_work_len(N, used, &wlen));
    work = xmalloc(wlen * sizeof *work);
    weights = xmalloc(used * sizeof *weights);
    OK(dk_elasticity_amg_pool_sizes(ncells, &graph, 2, fixed, N, 0, &amg, work, wlen, weights,
                                    used, &sizes));
    OK(dk_elasticity_amg_pool_sizes(ncells, &graph, 2, sfixed, N, 1, &amg, work, wlen,
                                    weights, used, &ssizes));
    rlen = sizes.reals > ssizes.reals ? sizes.reals : ssizes.reals;
    ilen = sizes.indices > ssizes.indices ? sizes.indices : ssizes.indices;
    CHECK(sizes.bytes == 0 && ssizes.reals > sizes.reals);
    reals = xmalloc(rlen * sizeof *reals);
    reals32 = xmalloc(rlen * sizeof *reals32);
    indices = xmalloc(ilen * sizeof *indices);
    pools.reals = reals;
    pools.reals_len = sizes.reals;
    pools.indices = indices;
    pools.indices_len = sizes.indices;
    pools.bytes = NULL;
    pools.bytes_len = 0;
    pools32.reals = reals32;
    pools32.reals_len = sizes.reals;
    pools32.indices = indices;
    pools32.indices_len = sizes.indices;
    pools32.bytes = NULL;
    pools32.bytes_len = 0;
    OK(dk_elasticity_sliding_scratch_len(N, ncells, used, 2, &slen));
    scratch = xmalloc(slen * sizeof *scratch);
    scratch32 = xmalloc(slen * sizeof *scratch32);

    OK(dk_elasticity_options_default(&o));
    o.steps = 2;
    OK(dk_elasticity_options_default_f32(&o32));
    o32.steps = 2;

    /* The whole boundary fixed, rigid-mode multigrid. */
    memcpy(moved, points, sizeof moved);
    OK(dk_elasticity_deform_amg(&cells, 0, NULL, 0, &graph, 2, fixed, N, &o, &amg, NULL, 0, disp,
                                2 * N, moved, 2 * N, &pools, &r));
    hex64("amg64", moved, 2 * N);
    report("amg64", &r);
    check_ends(moved, fixed);
    for (k = 0; k < 2 * N; k++) moved32[k] = (float)points[k];
    OK(dk_elasticity_deform_amg_f32(&cells1, 1, index_scratch, iscr_len, &graph, 2, fixed, N,
                                    &o32, &amg, NULL, 0, disp32, 2 * N, moved32, 2 * N,
                                    &pools32, &r));
    hex32("amg32", moved32, 2 * N);
    report("amg32", &r);

    /* Sliding bottom edge, block-Jacobi CG. */
    memcpy(moved, points, sizeof moved);
    OK(dk_elasticity_deform_sliding(&cells, 0, NULL, 0, &graph, 2, sfixed, N, &con, &o, NULL, 0,
                                    disp, 2 * N, moved, 2 * N, scratch, slen, &r));
    hex64("slide64", moved, 2 * N);
    report("slide64", &r);
    check_ends(moved, sfixed);
    for (k = 0; k < 2 * N; k++) moved32[k] = (float)points[k];
    OK(dk_elasticity_deform_sliding_f32(&cells1, 1, index_scratch, iscr_len, &graph, 2, sfixed,
                                        N, &con32, &o32, NULL, 0, disp32, 2 * N, moved32, 2 * N,
                                        scratch32, slen, &r));
    hex32("slide32", moved32, 2 * N);
    report("slide32", &r);

    /* Sliding bottom edge, rigid-mode multigrid. */
    pools.reals_len = pools32.reals_len = ssizes.reals;
    pools.indices_len = pools32.indices_len = ssizes.indices;
    memcpy(moved, points, sizeof moved);
    OK(dk_elasticity_deform_sliding_amg(&cells, 0, NULL, 0, &graph, 2, sfixed, N, &con, &o, &amg,
                                        NULL, 0, disp, 2 * N, moved, 2 * N, &pools, &r));
    hex64("slamg64", moved, 2 * N);
    report("slamg64", &r);
    check_ends(moved, sfixed);
    for (k = 0; k < 2 * N; k++) moved32[k] = (float)points[k];
    OK(dk_elasticity_deform_sliding_amg_f32(&cells1, 1, index_scratch, iscr_len, &graph, 2,
                                            sfixed, N, &con32, &o32, &amg, NULL, 0, disp32,
                                            2 * N, moved32, 2 * N, &pools32, &r));
    hex32("slamg32", moved32, 2 * N);
    report("slamg32", &r);

    /* Bad input: the status, and the points untouched. */
    memcpy(keep, points, sizeof keep);
    memcpy(moved, points, sizeof moved);
    pools.reals_len = ssizes.reals - 1;
    EXPECT(dk_elasticity_deform_sliding_amg(&cells, 0, NULL, 0, &graph, 2, sfixed, N, &con, &o,
                                            &amg, NULL, 0, disp, 2 * N, moved, 2 * N, &pools, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    pools.reals_len = sizes.reals;
    pools.indices_len = sizes.indices - 1;
    EXPECT(dk_elasticity_deform_amg(&cells, 0, NULL, 0, &graph, 2, fixed, N, &o, &amg, NULL, 0,
                                    disp, 2 * N, moved, 2 * N, &pools, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    pools.indices_len = sizes.indices;
    EXPECT(dk_elasticity_deform_amg(&cells, 0, NULL, 0, &graph, 4, fixed, N, &o, &amg, NULL, 0,
                                    disp, 2 * N, moved, 2 * N, &pools, &r),
           DK_ERR_INVALID_PARAMETER);
    amg.smoother = 9;
    EXPECT(dk_elasticity_deform_amg(&cells, 0, NULL, 0, &graph, 2, fixed, N, &o, &amg, NULL, 0,
                                    disp, 2 * N, moved, 2 * N, &pools, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_amg_pool_sizes(ncells, &graph, 2, fixed, N, 0, &amg, work, wlen,
                                        weights, used, &sizes),
           DK_ERR_INVALID_PARAMETER);
    amg.smoother = DK_AMG_CHEBYSHEV;
    EXPECT(dk_elasticity_amg_pool_sizes(ncells, &graph, 2, fixed, N, 2, &amg, work, wlen,
                                        weights, used, &sizes),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_amg_pool_sizes(ncells, &graph, 2, fixed, N, 0, &amg, work, wlen - 1,
                                        weights, used, &sizes),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(dk_elasticity_deform_sliding(&cells, 0, NULL, 0, &graph, 2, sfixed, N, &con, &o, NULL,
                                        0, disp, 2 * N, moved, 2 * N, scratch, slen - 1, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    /* The whole boundary fixed in the mask, but the bottom slides in the constraints. */
    EXPECT(dk_elasticity_deform_sliding(&cells, 0, NULL, 0, &graph, 2, fixed, N, &con, &o, NULL,
                                        0, disp, 2 * N, moved, 2 * N, scratch, slen, &r),
           DK_ERR_INVALID_PARAMETER);
    o.poisson = 0.5;
    EXPECT(dk_elasticity_deform_sliding(&cells, 0, NULL, 0, &graph, 2, sfixed, N, &con, &o, NULL,
                                        0, disp, 2 * N, moved, 2 * N, scratch, slen, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_sliding_scratch_len(N, ncells, used, 4, &slen),
           DK_ERR_INVALID_PARAMETER);
    SAME(moved, keep, sizeof keep);
    if (failures) return 1;
    printf("elasticity solvers: every check held\n");
    return 0;
}

/* Linear elasticity from C99: dk_elasticity_graph_len, dk_elasticity_graph,
 * dk_elasticity_scratch_len, dk_elasticity_options_default (and _f32) and
 * dk_elasticity_deform (and _f32) on a 6 x 6 node square of quads and triangles, its interior
 * jittered, whose boundary moves by the linear field (0.1 y, -0.05 x) in 3 increments with
 * inverse-volume moduli: double with 0-based cells, float with 1-based ones (offsets and
 * nodes).
 *
 * Prints the points, the displacement and the bits and reports of both runs, so
 * host-tests/tests/ffi/c_abi_elasticity.rs can compute the same with the kernel and compare the
 * text. Checks here: the fixed nodes end at points + displacement, and bad input (short
 * scratch, Poisson ratio 0.5, dim 4, an unknown modulus) returns its status and leaves the
 * points untouched. Ends with "elasticity: every check held" (exit 0), or prints each failed
 * check (exit 1). */
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
static double points[2 * N], disp[2 * N];
static uint8_t fixed[N];

/* Quads where (i + j) is odd, two triangles elsewhere; interior nodes jittered. */
static void build(void) {
    size_t i, j, k = 0;
    for (j = 0; j < S; j++) {
        for (i = 0; i < S; i++) {
            size_t n = i + S * j;
            int edge = i == 0 || j == 0 || i == S - 1 || j == S - 1;
            double jx = edge ? 0.0 : 0.05 * (double)((n * 7) % 5) - 0.1;
            double jy = edge ? 0.0 : 0.04 * (double)((n * 3) % 5) - 0.08;
            points[2 * n] = ((double)i + jx) / (S - 1);
            points[2 * n + 1] = ((double)j + jy) / (S - 1);
            fixed[n] = (uint8_t)edge;
            disp[2 * n] = edge ? 0.1 * points[2 * n + 1] : 0.0;
            disp[2 * n + 1] = edge ? -0.05 * points[2 * n] : 0.0;
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

/* The bits of a double. */
static unsigned long long dbits(double x) {
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return (unsigned long long)b;
}

int main(void) {
    uint32_t offsets[N + 1], *targets, *index_scratch;
    size_t tlen, used, slen, k;
    dk_cells cells, cells1;
    dk_graph graph;
    dk_elasticity_options o, o32;
    dk_elasticity_report r, r32;
    double *scratch, moved[2 * N], keep[2 * N];
    float *scratch32, moved32[2 * N], disp32[2 * N];
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
    index_scratch = xmalloc((ncells + 1 + coffs[ncells]) * sizeof *index_scratch);
    OK(dk_elasticity_graph_len(N, &cells, 0, NULL, 0, &tlen));
    targets = xmalloc(tlen * sizeof *targets);
    OK(dk_elasticity_graph(N, &cells, 0, NULL, 0, offsets, N + 1, targets, tlen, &used));
    graph.offsets = offsets;
    graph.offsets_len = N + 1;
    graph.targets = targets;
    graph.targets_len = used;
    OK(dk_elasticity_scratch_len(N, ncells, used, 2, &slen));
    scratch = xmalloc(slen * sizeof *scratch);
    scratch32 = xmalloc(slen * sizeof *scratch32);
    hex64("points", points, 2 * N);
    hex64("disp", disp, 2 * N);

    OK(dk_elasticity_options_default(&o));
    o.steps = 3;
    memcpy(moved, points, sizeof moved);
    OK(dk_elasticity_deform(&cells, 0, NULL, 0, &graph, 2, fixed, N, &o, NULL, 0, disp, 2 * N,
                            moved, 2 * N, scratch, slen, &r));
    hex64("f64", moved, 2 * N);
    printf("f64 report %zu %zu %zu %016llX %d\n", r.steps, r.iterations, r.max_step_iterations,
           dbits(r.residual), (int)r.converged);
    for (k = 0; k < N; k++) {
        if (fixed[k]) {
            CHECK(moved[2 * k] == points[2 * k] + disp[2 * k]);
            CHECK(moved[2 * k + 1] == points[2 * k + 1] + disp[2 * k + 1]);
        }
    }

    OK(dk_elasticity_options_default_f32(&o32));
    o32.steps = 3;
    for (k = 0; k < 2 * N; k++) {
        moved32[k] = (float)points[k];
        disp32[k] = (float)disp[k];
    }
    OK(dk_elasticity_deform_f32(&cells1, 1, index_scratch, ncells + 1 + coffs[ncells], &graph, 2,
                                fixed, N, &o32, NULL, 0, disp32, 2 * N, moved32, 2 * N,
                                scratch32, slen, &r32));
    hex32("f32", moved32, 2 * N);
    printf("f32 report %zu %zu %zu %016llX %d\n", r32.steps, r32.iterations,
           r32.max_step_iterations, dbits(r32.residual), (int)r32.converged);

    /* Bad input: the status, and the points untouched. */
    memcpy(keep, points, sizeof keep);
    memcpy(moved, points, sizeof moved);
    EXPECT(dk_elasticity_deform(&cells, 0, NULL, 0, &graph, 2, fixed, N, &o, NULL, 0, disp,
                                2 * N, moved, 2 * N, scratch, slen - 1, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    o.poisson = 0.5;
    EXPECT(dk_elasticity_deform(&cells, 0, NULL, 0, &graph, 2, fixed, N, &o, NULL, 0, disp,
                                2 * N, moved, 2 * N, scratch, slen, &r),
           DK_ERR_INVALID_PARAMETER);
    o.poisson = 0.3;
    o.modulus = 7;
    EXPECT(dk_elasticity_deform(&cells, 0, NULL, 0, &graph, 2, fixed, N, &o, NULL, 0, disp,
                                2 * N, moved, 2 * N, scratch, slen, &r),
           DK_ERR_INVALID_PARAMETER);
    o.modulus = DK_MODULUS_WALL_DISTANCE; /* without wall distances */
    EXPECT(dk_elasticity_deform(&cells, 0, NULL, 0, &graph, 2, fixed, N, &o, NULL, 0, disp,
                                2 * N, moved, 2 * N, scratch, slen, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_deform(&cells, 0, NULL, 0, &graph, 4, fixed, N, &o, NULL, 0, disp,
                                2 * N, moved, 2 * N, scratch, slen, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_scratch_len(N, ncells, used, 1, &slen), DK_ERR_INVALID_PARAMETER);
    SAME(moved, keep, sizeof keep);
    if (failures) return 1;
    printf("elasticity: every check held\n");
    return 0;
}

/* The stateless multigrid spring solves from C99: dk_spring_solve_linear_amg and
 * dk_spring_solve_angle_amg (f64 and f32) with their pool-size queries, on a graded,
 * triangulated 64 x 48 grid (3,072 nodes, first row spacing 1e-3, growth 1.15: stretched cells
 * near the "wall" j = 0, where the one-level methods crawl).
 *
 * Prints the mesh's points and boundary data, the pool sizes, and the bits and reports of the
 * multigrid solves, so host-tests/tests/ffi/c_abi_solvers.rs can compute the same with the
 * kernel's AmgHierarchy::setup + solve_linear_amg / solve_angle_amg and compare the text;
 * prints the iteration counts of the one-level solves on the same problems (CG + Jacobi,
 * block-Jacobi angle CG), which must be at least 4 times higher. Bad input (NULL structs,
 * pools one element short, a work or hierarchy buffer too short, bad options) must return its
 * status and leave values, report and sizes bit-for-bit untouched. The per-precision part is
 * solvers_amg_body.c, included for double and for float. Ends with
 * "solvers_amg: every check held" (exit 0), or prints each failed check (exit 1). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

/* ---- The mesh (shared by both precisions). ---- */

#define NI 64
#define NJ 48
#define N (NI * NJ)
/* Edges: i-direction, j-direction and one diagonal per cell. */
#define EDGES ((NI - 1) * NJ + NI * (NJ - 1) + (NI - 1) * (NJ - 1))

static uint32_t offsets[N + 1], targets[2 * EDGES];
static size_t used;
static dk_graph graph;
static double points[2 * N];   /* x, y of node i + NI j */
static double values0[2 * N];  /* boundary displacements, 0 at free nodes */
static uint8_t fixed[N];

static void build_mesh(void) {
    uint32_t *edges = xmalloc(2 * EDGES * sizeof *edges);
    size_t k = 0, i, j;
    double y = 0, dy = 1e-3;
    /* A rotation of the wall j = 0 by 0.1 rad about (1.6, 0). */
    const double c = 0.99500416527802582, s = 0.099833416646828155, xc = 1.6;
    for (j = 0; j < NJ; j++) {
        for (i = 0; i < NI; i++) {
            size_t n = i + NI * j;
            points[2 * n] = 0.05 * (double)i;
            points[2 * n + 1] = y;
            fixed[n] = (uint8_t)(i == 0 || j == 0 || i == NI - 1 || j == NJ - 1);
            values0[2 * n] = 0;
            values0[2 * n + 1] = 0;
            if (j == 0) {
                double x = points[2 * n] - xc;
                values0[2 * n] = (c - 1) * x;
                values0[2 * n + 1] = s * x;
            }
            if (i + 1 < NI) {
                edges[k++] = (uint32_t)n;
                edges[k++] = (uint32_t)(n + 1);
            }
            if (j + 1 < NJ) {
                edges[k++] = (uint32_t)n;
                edges[k++] = (uint32_t)(n + NI);
            }
            if (i + 1 < NI && j + 1 < NJ) {
                edges[k++] = (uint32_t)n;
                edges[k++] = (uint32_t)(n + NI + 1);
            }
        }
        y += dy;
        dy *= 1.15;
    }
    CHECK(k == 2 * EDGES);
    OK(dk_graph_from_edges(N, edges, k / 2 * 2, 0, NULL, 0, offsets, N + 1, targets, 2 * EDGES,
                           &used));
    CHECK(used == 2 * EDGES);
    graph.offsets = offsets;
    graph.offsets_len = N + 1;
    graph.targets = targets;
    graph.targets_len = used;
    free(edges);
}

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define STR_(a) #a
#define STR(a) STR_(a)

#define REAL double
#define FN(name) name
#define SUF f64
#define HEX hex64
#include "solvers_amg_body.c"
#undef REAL
#undef FN
#undef SUF
#undef HEX

#define REAL float
#define FN(name) name##_f32
#define SUF f32
#define HEX hex32
#include "solvers_amg_body.c"

static void precision_independent(void) {
    dk_amg_options a;
    size_t len = 99;
    OK(dk_amg_options_default(&a));
    CHECK(a.strength_theta == 0.25 && a.max_levels == 10 && a.max_coarse == 256);
    CHECK(a.sweeps == 2 && a.smoother == DK_AMG_CHEBYSHEV);
    {
        /* The plans' default multigrid options are the same. */
        dk_plan_options p;
        OK(dk_plan_options_default(&p));
        CHECK(p.amg.strength_theta == a.strength_theta && p.amg.max_levels == a.max_levels);
        CHECK(p.amg.max_coarse == a.max_coarse && p.amg.sweeps == a.sweeps);
        CHECK(p.amg.smoother == a.smoother);
    }
    EXPECT(dk_amg_options_default(NULL), DK_ERR_NULL_POINTER);
    OK(dk_spring_amg_work_len(10, 36, &len));
    CHECK(len == 4 * 46 + 64);
    len = 99;
    EXPECT(dk_spring_amg_work_len(SIZE_MAX / 2, 1, &len), DK_ERR_TOO_LARGE);
    EXPECT(dk_spring_amg_work_len(SIZE_MAX, 1, &len), DK_ERR_TOO_LARGE);
    CHECK(len == 99);
    EXPECT(dk_spring_amg_work_len(10, 36, NULL), DK_ERR_NULL_POINTER);
}

int main(void) {
    build_mesh();
    hex64("points", points, 2 * N);
    hex64("values0", values0, 2 * N);
    precision_independent();
    run_f64();
    run_f32();
    if (failures) {
        printf("solvers_amg: %d checks failed\n", failures);
        return 1;
    }
    printf("solvers_amg: every check held\n");
    return 0;
}

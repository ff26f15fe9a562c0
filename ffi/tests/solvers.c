/* The solver ABI (springs, quality, Taubin) from C99: every dk_spring_*, dk_quality_*,
 * dk_taubin_* and option-default function, in f64 and f32, on small cases whose answer is
 * known independently (linear fields, maximum principle, symmetry, hand-computed values),
 * and bad input (NULL, wrong lengths, out-of-range indices, index_base 2, NaN) that must
 * return the documented status and leave every output bit-for-bit untouched.
 *
 * The per-precision checks live in solvers_body.c, included once for double and once for
 * float. Prints "solvers: every check held" and exits 0 on success; prints each failed check
 * and exits 1 otherwise. */
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <string.h>

#include "deform_kernel.h"

/* index_scratch for the 1-based quality calls of solvers_body.c (0-based copies of the cell
 * and wall arrays; the largest call reads 16 indices). */
#define ISCR_LEN 64
static uint32_t iscr[ISCR_LEN];

#include "check.h"

#define CLOSE(a, b, tol)                                                                  \
    do {                                                                                  \
        double a_ = (double)(a), b_ = (double)(b);                                        \
        if (!(fabs(a_ - b_) <= (tol))) {                                                  \
            printf("FAIL line %d: %s = %.17g, expected %s = %.17g\n", __LINE__, #a, a_,   \
                   #b, b_);                                                               \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

/* Pointers to C99 compound literals of the ABI's parameter structs, for the calls whose arrays
 * differ from a named struct's (mostly bad input). SYSTEM takes a dk_graph pointer and builds
 * the spring system of the precision being compiled (FN, set around each include of
 * solvers_body.c). */
#define GRAPH(off, off_len, tgt, tgt_len) (&(dk_graph){(off), (off_len), (tgt), (tgt_len)})
#define CELLS(off, off_len, nodes, nodes_len, kinds, kinds_len)                             \
    (&(dk_cells){(off), (off_len), (nodes), (nodes_len), (kinds), (kinds_len)})
#define SYSTEM(graph, k, k_len, fixed, fixed_len)                                           \
    (&(FN(dk_spring_system)){*(graph), (k), (k_len), (fixed), (fixed_len)})

/* ---- Graphs shared by both precisions (built with dk_graph_from_edges). ---- */

/* A chain 0 - 1 - 2 - 3 - 4. */
#define CHAIN_N 5
static uint32_t chain_off[CHAIN_N + 1], chain_tgt[2 * (CHAIN_N - 1)];
static size_t chain_e;

/* A 4 x 4 grid graph (node i + 4 j), 4-neighbour edges. */
#define GRID_N 16
static uint32_t grid_off[GRID_N + 1], grid_tgt[48];
static size_t grid_e;

/* A square with a centre node: corners 0..3 (fixed), centre 4, edges around the square and
 * from every corner to the centre (4 triangles). */
#define FAN_N 5
static uint32_t fan_off[FAN_N + 1], fan_tgt[16];
static size_t fan_e;

/* 3 x 3 nodes of a 2 x 2 quad mesh (node i + 3 j), with its edge graph. */
static uint32_t q9_off[10], q9_tgt[24];
static size_t q9_e;

/* The four graphs as the ABI takes them (every array at its full length). */
static const dk_graph chain_graph = {chain_off, CHAIN_N + 1, chain_tgt, 2 * (CHAIN_N - 1)};
static const dk_graph grid_graph = {grid_off, GRID_N + 1, grid_tgt, 48};
static const dk_graph fan_graph = {fan_off, FAN_N + 1, fan_tgt, 16};
static const dk_graph q9_graph = {q9_off, 10, q9_tgt, 24};

static void build_graphs(void) {
    uint32_t edges[64];
    size_t k = 0, i, j;
    for (i = 0; i + 1 < CHAIN_N; i++) {
        edges[k++] = (uint32_t)i;
        edges[k++] = (uint32_t)(i + 1);
    }
    OK(dk_graph_from_edges(CHAIN_N, edges, k, 0, NULL, 0, chain_off, CHAIN_N + 1, chain_tgt,
                           2 * (CHAIN_N - 1), &chain_e));
    k = 0;
    for (j = 0; j < 4; j++)
        for (i = 0; i < 4; i++) {
            if (i + 1 < 4) {
                edges[k++] = (uint32_t)(i + 4 * j);
                edges[k++] = (uint32_t)(i + 1 + 4 * j);
            }
            if (j + 1 < 4) {
                edges[k++] = (uint32_t)(i + 4 * j);
                edges[k++] = (uint32_t)(i + 4 * (j + 1));
            }
        }
    OK(dk_graph_from_edges(GRID_N, edges, k, 0, NULL, 0, grid_off, GRID_N + 1, grid_tgt, 48,
                           &grid_e));
    {
        /* 1-based on purpose: the builder converts. */
        const uint32_t fan_edges[16] = {1, 2, 2, 3, 3, 4, 4, 1, 1, 5, 2, 5, 3, 5, 4, 5};
        uint32_t fan_scratch[16]; /* their 0-based copy */
        OK(dk_graph_from_edges(FAN_N, fan_edges, 16, 1, fan_scratch, 16, fan_off, FAN_N + 1,
                               fan_tgt, 16, &fan_e));
    }
    k = 0;
    for (j = 0; j < 3; j++)
        for (i = 0; i < 3; i++) {
            if (i + 1 < 3) {
                edges[k++] = (uint32_t)(i + 3 * j);
                edges[k++] = (uint32_t)(i + 1 + 3 * j);
            }
            if (j + 1 < 3) {
                edges[k++] = (uint32_t)(i + 3 * j);
                edges[k++] = (uint32_t)(i + 3 * (j + 1));
            }
        }
    OK(dk_graph_from_edges(9, edges, k, 0, NULL, 0, q9_off, 10, q9_tgt, 24, &q9_e));
    CHECK(chain_e == 8 && grid_e == 48 && fan_e == 16 && q9_e == 24);
}

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)

#define REAL double
#define FN(name) name
#define SUF f64
#define TOL 1e-12
#define LOOSE 1e-9
#include "solvers_body.c"
#undef REAL
#undef FN
#undef SUF
#undef TOL
#undef LOOSE

#define REAL float
#define FN(name) name##_f32
#define SUF f32
#define TOL 2e-6
#define LOOSE 2e-4
#include "solvers_body.c"

static void precision_independent(void) {
    size_t len = 99, sentinel_len = 99;
    dk_smooth_arclength_options o, o_copy;
    dk_taubin_coarse c = {{2, 1, 1}, DK_PROLONGATION_VALUES};

    /* Size queries that do not depend on the precision. */
    OK(dk_taubin_smooth_structured_scratch_len(4, 3, 2, &len));
    CHECK(len == 24);
    EXPECT(dk_taubin_smooth_structured_scratch_len(0, 3, 2, &len), DK_ERR_BAD_DIMENSIONS);
    EXPECT(dk_taubin_smooth_structured_scratch_len(4, 3, 2, NULL), DK_ERR_NULL_POINTER);
    OK(dk_taubin_smooth_structured_coarse_scratch_len(9, 1, 1, &c, &len));
    CHECK(len == 10); /* coarse indices 0, 2, 4, 6, 8: two fields of 5 */
    c.factor[0] = 0;
    len = sentinel_len;
    EXPECT(dk_taubin_smooth_structured_coarse_scratch_len(9, 1, 1, &c, &len),
           DK_ERR_INVALID_PARAMETER);
    CHECK(len == sentinel_len);
    EXPECT(dk_taubin_smooth_structured_coarse_scratch_len(9, 1, 1, NULL, &len),
           DK_ERR_NULL_POINTER);
    OK(dk_taubin_smooth_graph_scratch_len(10, 3, &len));
    CHECK(len == 30);
    EXPECT(dk_taubin_smooth_graph_scratch_len(10, 0, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_taubin_smooth_graph_scratch_len(10, 8, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_taubin_smooth_graph_scratch_len(SIZE_MAX, 2, &len), DK_ERR_TOO_LARGE);
    OK(dk_taubin_redistribute_scratch_len(5, 4, 3, 3, 1, &len));
    CHECK(len == 16); /* (dim + 1) * points per j-line */
    len = sentinel_len;
    EXPECT(dk_taubin_redistribute_scratch_len(5, 4, 3, 3, 3, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_taubin_redistribute_scratch_len(5, 4, 3, 4, 1, &len), DK_ERR_INVALID_PARAMETER);
    CHECK(len == sentinel_len);

    OK(dk_smooth_arclength_options_default(2, &o));
    CHECK(o.lambda == 0.330 && o.mu == -0.334 && o.iterations == 30);
    CHECK(o.coarse_iterations == 15 && o.pinned == NULL && o.pinned_len == 0);
    CHECK(o.direction == 2 && o.normalised == 0 && o.use_coarse == 0);
    CHECK(o.mirror[0] == 0 && o.mirror[1] == 0 && o.mirror[2] == 0);
    CHECK(o.coarse.factor[0] == 1 && o.coarse.prolongation == DK_PROLONGATION_VALUES);
    OK(dk_taubin_smooth_arclength_scratch_len(6, 1, 1, &o, 2, &len));
    /* n + max(n, (dim + 1) * 1) for k-lines of a 6 x 1 x 1 block: 6 + 6 */
    CHECK(len == 12);
    o.direction = 0;
    OK(dk_taubin_smooth_arclength_scratch_len(6, 1, 1, &o, 2, &len));
    CHECK(len == 6 + 18); /* n + 3 * 6 */
    o.use_coarse = 1;
    o.coarse.factor[0] = 2;
    OK(dk_taubin_smooth_arclength_scratch_len(6, 1, 1, &o, 3, &len));
    CHECK(len == 6 + 24); /* n + max(6, 2 * 4, 4 * 6) */
    o.coarse.prolongation = 7;
    len = sentinel_len;
    EXPECT(dk_taubin_smooth_arclength_scratch_len(6, 1, 1, &o, 3, &len),
           DK_ERR_INVALID_PARAMETER);
    o.coarse.prolongation = DK_PROLONGATION_VALUES;
    EXPECT(dk_taubin_smooth_arclength_scratch_len(6, 1, 1, &o, 4, &len),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_taubin_smooth_arclength_scratch_len(6, 0, 1, &o, 2, &len),
           DK_ERR_BAD_DIMENSIONS);
    EXPECT(dk_taubin_smooth_arclength_scratch_len(6, 1, 1, NULL, 2, &len), DK_ERR_NULL_POINTER);
    CHECK(len == sentinel_len);
    POISON(o);
    o_copy = o;
    EXPECT(dk_smooth_arclength_options_default(3, &o), DK_ERR_INVALID_PARAMETER);
    SAME(&o, &o_copy, sizeof o);
    EXPECT(dk_smooth_arclength_options_default(0, NULL), DK_ERR_NULL_POINTER);

    OK(dk_spring_index_scratch_len(17, &len));
    CHECK(len == 17);
    EXPECT(dk_spring_index_scratch_len(17, NULL), DK_ERR_NULL_POINTER);
    OK(dk_spring_angle_rigidity_probe_scratch_len(10, 3, &len));
    CHECK(len == 120);
    len = sentinel_len;
    EXPECT(dk_spring_angle_rigidity_probe_scratch_len(10, 1, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_spring_angle_rigidity_probe_scratch_len(SIZE_MAX / 2, 2, &len),
           DK_ERR_TOO_LARGE);
    CHECK(len == sentinel_len);
    OK(dk_quality_wall_angle_scratch_len(10, 2, &len));
    CHECK(len == 40);
    len = sentinel_len;
    EXPECT(dk_quality_wall_angle_scratch_len(10, 5, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_quality_wall_angle_scratch_len(SIZE_MAX, 2, &len), DK_ERR_TOO_LARGE);
    CHECK(len == sentinel_len);
    {
        dk_spring_solve_options so;
        OK(dk_spring_solve_options_default(&so));
        so.method = DK_LINEAR_JACOBI;
        OK(dk_spring_solve_linear_scratch_len(10, 3, &so, &len));
        CHECK(len == 30);
        so.method = DK_LINEAR_GAUSS_SEIDEL;
        OK(dk_spring_solve_linear_scratch_len(10, 3, &so, &len));
        CHECK(len == 0);
        so.method = DK_LINEAR_SOR;
        OK(dk_spring_solve_linear_scratch_len(10, 3, &so, &len));
        CHECK(len == 0);
        so.method = DK_LINEAR_CG;
        OK(dk_spring_solve_linear_scratch_len(10, 3, &so, &len));
        CHECK(len == 150);
        len = sentinel_len;
        so.method = 9;
        EXPECT(dk_spring_solve_linear_scratch_len(10, 3, &so, &len), DK_ERR_INVALID_PARAMETER);
        so.method = DK_LINEAR_CG;
        so.preconditioner = 9;
        EXPECT(dk_spring_solve_linear_scratch_len(10, 3, &so, &len), DK_ERR_INVALID_PARAMETER);
        so.preconditioner = DK_PRECONDITIONER_NONE;
        EXPECT(dk_spring_solve_linear_scratch_len(10, 8, &so, &len), DK_ERR_INVALID_PARAMETER);
        EXPECT(dk_spring_solve_linear_scratch_len(SIZE_MAX / 2, 1, &so, &len),
               DK_ERR_TOO_LARGE);
        EXPECT(dk_spring_solve_linear_scratch_len(10, 3, NULL, &len), DK_ERR_NULL_POINTER);
        CHECK(len == sentinel_len);
    }
}

int main(void) {
    build_graphs();
    precision_independent();
    run_f64();
    run_f32();
    if (failures) {
        printf("solvers: %d checks failed\n", failures);
        return 1;
    }
    printf("solvers: every check held\n");
    return 0;
}

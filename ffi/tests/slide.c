/* Sliding boundaries (symmetry planes) from C99: dk_constraints, dk_constraints_fixed_mask,
 * dk_fit_plane, dk_slide_points and the sliding spring solves (dk_spring_solve_linear_sliding,
 * dk_spring_solve_angle_sliding and their multigrid variants, f64 and f32) on a 2D half
 * annulus (65 x 17 nodes, r 0.5 to 2, graded radially, triangulated) rotated by 0.3 rad, whose
 * symmetry line (both straight edges) slides: the inner circle moves 0.3 along the line, the
 * outer circle is fixed.
 *
 * Prints the mesh's points and boundary data, the fitted line, and the bits and reports of
 * every solve and of dk_slide_points, so host-tests/tests/ffi/c_abi_slide.rs can compute the same
 * with the kernel (slide::fit_plane, Constraints, solve_linear_sliding, solve_angle_sliding,
 * AmgHierarchy::setup + the multigrid variants, slide_points) and compare the text. Checks
 * here: every sliding node's displacement stays on the line (|n.d| <= 1e-12 |d| in double,
 * 1e-6 |d| in float), fixed nodes keep their values, and bad input (NULL, wrong lengths, a
 * kind above 3, a direction not unit or not finite, a mask that does not match the
 * constraints, short scratch or pools, bad dim/omega) returns its status and leaves values,
 * report and outputs bit-for-bit untouched. The per-precision part is slide_body.c, included
 * for double and for float. Ends with "slide: every check held" (exit 0), or prints each
 * failed check (exit 1). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

/* ---- The mesh (shared by both precisions). ---- */

#define NT 65 /* nodes around (theta 0 to pi) */
#define NR 17 /* nodes across (r 0.5 to 2) */
#define N (NT * NR)
/* Edges: around, across and one diagonal per cell. */
#define EDGES ((NT - 1) * NR + NT * (NR - 1) + (NT - 1) * (NR - 1))
#define NSYM (2 * NR)

static uint32_t offsets[N + 1], targets[2 * EDGES];
static size_t used;
static dk_graph graph;
static double points[2 * N];  /* x, y of node k + NT j */
static double values0[2 * N]; /* the inner circle's displacement, 0 elsewhere */
static uint8_t kinds[N];      /* 1 on both circles, 2 on the symmetry line, else 0 */
static uint32_t sym[NSYM], sym1[NSYM]; /* the symmetry line's nodes, 0- and 1-based */

static void build_mesh(void) {
    uint32_t *edges = xmalloc(2 * EDGES * sizeof *edges);
    size_t k = 0, e = 0, i, j;
    const double pi = 3.14159265358979323846;
    /* The whole mesh rotated by 0.3 rad: the symmetry line is not an axis. */
    const double c = 0.95533648912560598, s = 0.29552020666133955;
    for (j = 0; j < NR; j++) {
        double r = 0.5 * pow(4.0, (double)j / (NR - 1));
        for (i = 0; i < NT; i++) {
            size_t n = i + NT * j;
            double t = pi * (double)i / (NT - 1), x = r * cos(t), y = r * sin(t);
            if (i == NT - 1) y = 0; /* sin(pi) is not 0 in floating point */
            if (i == 0) y = 0;
            points[2 * n] = c * x - s * y;
            points[2 * n + 1] = s * x + c * y;
            kinds[n] = (uint8_t)((j == 0 || j == NR - 1) ? 1 : (i == 0 || i == NT - 1) ? 2 : 0);
            values0[2 * n] = j == 0 ? 0.3 * c : 0;
            values0[2 * n + 1] = j == 0 ? 0.3 * s : 0;
            if (i == 0 || i == NT - 1) {
                sym[k] = (uint32_t)n;
                sym1[k] = (uint32_t)n + 1;
                k++;
            }
            if (i + 1 < NT) {
                edges[e++] = (uint32_t)n;
                edges[e++] = (uint32_t)(n + 1);
            }
            if (j + 1 < NR) {
                edges[e++] = (uint32_t)n;
                edges[e++] = (uint32_t)(n + NT);
            }
            if (i + 1 < NT && j + 1 < NR) {
                edges[e++] = (uint32_t)n;
                edges[e++] = (uint32_t)(n + NT + 1);
            }
        }
    }
    CHECK(k == NSYM);
    CHECK(e == 2 * EDGES);
    OK(dk_graph_from_edges(N, edges, e, 0, NULL, 0, offsets, N + 1, targets, 2 * EDGES, &used));
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
#define TOL 1e-12
#include "slide_body.c"
#undef REAL
#undef FN
#undef SUF
#undef HEX
#undef TOL

#define REAL float
#define FN(name) name##_f32
#define SUF f32
#define HEX hex32
#define TOL 1e-6
#include "slide_body.c"

static void precision_independent(void) {
    dk_spring_solve_options o;
    size_t len = 99, len1 = 99;
    OK(dk_spring_solve_options_default(&o));
    OK(dk_spring_solve_linear_sliding_scratch_len(10, 2, &o, &len));
    CHECK(len == 6 * 10 * 2); /* CG */
    o.method = DK_LINEAR_JACOBI;
    OK(dk_spring_solve_linear_sliding_scratch_len(10, 3, &o, &len));
    CHECK(len == 2 * 10 * 3);
    o.method = DK_LINEAR_GAUSS_SEIDEL;
    OK(dk_spring_solve_linear_sliding_scratch_len(10, 2, &o, &len));
    CHECK(len == 10 * 2);
    o.method = DK_LINEAR_SOR;
    OK(dk_spring_solve_linear_sliding_scratch_len(10, 2, &o, &len1));
    CHECK(len1 == len);
    len = 99;
    EXPECT(dk_spring_solve_linear_sliding_scratch_len(10, 1, &o, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_spring_solve_linear_sliding_scratch_len(10, 4, &o, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_spring_solve_linear_sliding_scratch_len(SIZE_MAX / 4, 2, &o, &len),
           DK_ERR_TOO_LARGE);
    EXPECT(dk_spring_solve_linear_sliding_scratch_len(10, 2, NULL, &len), DK_ERR_NULL_POINTER);
    o.method = 9;
    EXPECT(dk_spring_solve_linear_sliding_scratch_len(10, 2, &o, &len), DK_ERR_INVALID_PARAMETER);
    CHECK(len == 99);
    EXPECT(dk_spring_solve_linear_sliding_scratch_len(10, 2, NULL, NULL), DK_ERR_NULL_POINTER);
    {
        dk_spring_angle_options a;
        OK(dk_spring_angle_options_default(&a));
        OK(dk_spring_solve_angle_sliding_scratch_len(10, 2, &a, &len)); /* direct GS */
        CHECK(len == 10 * 2);
        a.method = DK_ANGLE_DIRECT_JACOBI;
        OK(dk_spring_solve_angle_sliding_scratch_len(10, 3, &a, &len));
        CHECK(len == 2 * 10 * 3);
        a.method = DK_ANGLE_CG;
        OK(dk_spring_solve_angle_sliding_scratch_len(10, 2, &a, &len));
        CHECK(len == 5 * 10 * 2);
        a.method = DK_ANGLE_DIRECT_GAUSS_SEIDEL;
        a.epsilon = 0; /* the rigidity probe's 4 n */
        OK(dk_spring_solve_angle_sliding_scratch_len(10, 2, &a, &len));
        CHECK(len == 4 * 10 * 2);
        a.epsilon = 1e-300; /* 0 in float */
        OK(dk_spring_solve_angle_sliding_scratch_len(10, 2, &a, &len));
        OK(dk_spring_solve_angle_sliding_scratch_len_f32(10, 2, &a, &len1));
        CHECK(len == 10 * 2 && len1 == 4 * 10 * 2);
        len = 99;
        a.method = 3;
        EXPECT(dk_spring_solve_angle_sliding_scratch_len(10, 2, &a, &len),
               DK_ERR_INVALID_PARAMETER);
        CHECK(len == 99);
    }
}

int main(void) {
    build_mesh();
    hex64("points", points, 2 * N);
    hex64("values0", values0, 2 * N);
    precision_independent();
    run_f64();
    run_f32();
    if (failures) {
        printf("slide: %d checks failed\n", failures);
        return 1;
    }
    printf("slide: every check held\n");
    return 0;
}

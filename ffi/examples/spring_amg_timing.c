/* The stateless multigrid spring solves against the one-level ones, timed from C.
 *
 *   cc -O2 -std=c99 -I ffi/generated ffi/examples/spring_amg_timing.c \
 *      ffi/capi/target/release/libdeform_kernel.a -lm -lpthread -ldl -o amg_timing
 *   ./amg_timing 256 192      # NI x NJ nodes (default 64 x 48)
 *
 * A triangulated NI x NJ grid on [0, 3.2] x [0, y_max], rows graded from a first spacing of
 * 1e-3 by the factor 1 + 6 / NJ, Batina stiffness, the row j = 0 rotated 0.1 rad about
 * (1.6, 0), the other boundary fixed at zero; both displacement components, relative residual
 * 1e-8. Prints the pool-size query's time (the multigrid symbolic pass), then iterations and
 * wall time of dk_spring_solve_linear_amg (hierarchy setup included) against
 * dk_spring_solve_linear (CG + Jacobi), and of dk_spring_solve_angle_amg against
 * dk_spring_solve_angle (block-Jacobi CG), epsilon 0.1. host-tests/tests/ffi/c_abi_solvers.rs
 * builds and runs it at the default size. */
#define _POSIX_C_SOURCE 199309L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "deform_kernel.h"

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void *xmalloc(size_t bytes) {
    void *p = malloc(bytes ? bytes : 1);
    if (!p) {
        fprintf(stderr, "out of memory\n");
        exit(2);
    }
    return p;
}

static void check(dk_status s, const char *what) {
    if (s != DK_OK) {
        fprintf(stderr, "%s: %s\n", what, dk_status_str((int32_t)s));
        exit(1);
    }
}

int main(int argc, char **argv) {
    size_t ni = argc > 1 ? (size_t)atoi(argv[1]) : 64, nj = argc > 2 ? (size_t)atoi(argv[2]) : 48;
    size_t n, e, k = 0, i, j, used, work_len, need;
    uint32_t *edges, *offsets, *targets, *work, *index_scratch;
    double *points, *values0, *values, *stiffness, *scratch;
    uint8_t *fixed;
    double y = 0, dy = 1e-3, growth, t0, t1;
    const double c = 0.99500416527802582, s = 0.099833416646828155;
    dk_graph graph;
    dk_spring_system sys;
    dk_amg_options amg;
    dk_spring_solve_options linear;
    dk_spring_angle_options angle;
    dk_plan_sizes sizes;
    dk_plan_pools pools;
    dk_spring_solve_report r;

    if (ni < 3 || nj < 3) {
        fprintf(stderr, "usage: %s [NI NJ], both at least 3\n", argv[0]);
        return 2;
    }
    n = ni * nj;
    e = (ni - 1) * nj + ni * (nj - 1) + (ni - 1) * (nj - 1);
    growth = 1.0 + 6.0 / (double)nj;
    edges = xmalloc(2 * e * sizeof *edges);
    offsets = xmalloc((n + 1) * sizeof *offsets);
    targets = xmalloc(2 * e * sizeof *targets);
    index_scratch = xmalloc(n * sizeof *index_scratch);
    points = xmalloc(2 * n * sizeof *points);
    values0 = xmalloc(2 * n * sizeof *values0);
    values = xmalloc(2 * n * sizeof *values);
    stiffness = xmalloc(2 * e * sizeof *stiffness);
    fixed = xmalloc(n);
    for (j = 0; j < nj; j++) {
        for (i = 0; i < ni; i++) {
            size_t m = i + ni * j;
            points[2 * m] = 3.2 * (double)i / (double)(ni - 1);
            points[2 * m + 1] = y;
            fixed[m] = (uint8_t)(i == 0 || j == 0 || i == ni - 1 || j == nj - 1);
            values0[2 * m] = 0;
            values0[2 * m + 1] = 0;
            if (j == 0) {
                values0[2 * m] = (c - 1) * (points[2 * m] - 1.6);
                values0[2 * m + 1] = s * (points[2 * m] - 1.6);
            }
            if (i + 1 < ni) {
                edges[k++] = (uint32_t)m;
                edges[k++] = (uint32_t)(m + 1);
            }
            if (j + 1 < nj) {
                edges[k++] = (uint32_t)m;
                edges[k++] = (uint32_t)(m + ni);
            }
            if (i + 1 < ni && j + 1 < nj) {
                edges[k++] = (uint32_t)m;
                edges[k++] = (uint32_t)(m + ni + 1);
            }
        }
        y += dy;
        dy *= growth;
    }
    check(dk_graph_from_edges(n, edges, k, 0, NULL, 0, offsets, n + 1, targets, 2 * e, &used),
          "graph");
    graph.offsets = offsets;
    graph.offsets_len = n + 1;
    graph.targets = targets;
    graph.targets_len = used;
    check(dk_spring_batina_stiffness(&graph, points, 2 * n, 2, 1, stiffness, used), "stiffness");
    sys.graph = graph;
    sys.stiffness = stiffness;
    sys.stiffness_len = used;
    sys.fixed = fixed;
    sys.fixed_len = n;

    check(dk_amg_options_default(&amg), "amg options");
    check(dk_spring_solve_options_default(&linear), "linear options");
    linear.residual_tol = 1e-8;
    check(dk_spring_angle_options_default(&angle), "angle options");
    angle.method = DK_ANGLE_CG;
    angle.epsilon = 0.1;
    angle.residual_tol = 1e-8;

    /* Symbolic first: the exact pools, then the solves. */
    check(dk_spring_amg_work_len(n, used, &work_len), "work length");
    work = xmalloc(work_len * sizeof *work);
    t0 = now();
    check(dk_spring_solve_linear_amg_pool_sizes(&sys, 2, &amg, work, work_len, &sizes),
          "pool sizes");
    t1 = now();
    free(work);
    printf("%zu nodes: pool-size query %.3f s (reals %zu, indices %zu)\n", n, t1 - t0,
           sizes.reals, sizes.indices);
    pools.reals = xmalloc(sizes.reals * sizeof(double));
    pools.reals_len = sizes.reals;
    pools.indices = xmalloc(sizes.indices * sizeof(uint32_t));
    pools.indices_len = sizes.indices;
    pools.bytes = NULL;
    pools.bytes_len = 0;

    memcpy(values, values0, 2 * n * sizeof *values);
    t0 = now();
    check(dk_spring_solve_linear_amg(&sys, &linear, &amg, 2, values, 2 * n, &pools, &r),
          "linear amg");
    t1 = now();
    printf("linear, multigrid (setup + solve): %zu iterations, converged %d, %.3f s\n",
           r.iterations, (int)r.converged, t1 - t0);
    check(dk_spring_solve_linear_scratch_len(n, 2, &linear, &need), "scratch length");
    scratch = xmalloc(need * sizeof *scratch);
    memcpy(values, values0, 2 * n * sizeof *values);
    t0 = now();
    check(dk_spring_solve_linear(&sys, &linear, 2, values, 2 * n, scratch, need, index_scratch,
                                 n, &r),
          "linear cg");
    t1 = now();
    printf("linear, CG + Jacobi: %zu iterations, converged %d, %.3f s\n", r.iterations,
           (int)r.converged, t1 - t0);
    free(scratch);

    /* The angle pools have the linear ones' lengths for dim = components = 2. */
    memcpy(values, values0, 2 * n * sizeof *values);
    t0 = now();
    check(dk_spring_solve_angle_amg(&sys, points, 2 * n, 2, &angle, &amg, values, 2 * n, &pools,
                                    &r),
          "angle amg");
    t1 = now();
    printf("angle, multigrid (setup + solve): %zu iterations, converged %d, %.3f s\n",
           r.iterations, (int)r.converged, t1 - t0);
    check(dk_spring_solve_angle_scratch_len(n, 2, &angle, &need), "angle scratch length");
    scratch = xmalloc(need * sizeof *scratch);
    memcpy(values, values0, 2 * n * sizeof *values);
    t0 = now();
    check(dk_spring_solve_angle(&sys, points, 2 * n, 2, &angle, values, 2 * n, scratch, need,
                                index_scratch, n, &r),
          "angle cg");
    t1 = now();
    printf("angle, block-Jacobi CG: %zu iterations, converged %d, %.3f s\n", r.iterations,
           (int)r.converged, t1 - t0);

    free(scratch);
    free(pools.reals);
    free(pools.indices);
    free(edges);
    free(offsets);
    free(targets);
    free(index_scratch);
    free(points);
    free(values0);
    free(values);
    free(stiffness);
    free(fixed);
    return 0;
}

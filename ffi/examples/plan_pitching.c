/* A flow solver's view of deform-kernel: a prepared plan stepped every time step.
 *
 * An O-grid around an elliptic section (NI points around, NJ rings out to a far field at 10
 * chords) pitches about its quarter chord, ±5° over 20 time steps. The plan (graph,
 * stiffness, multigrid hierarchy, boundary data) is built once in three caller pools; each
 * step passes only the new boundary positions, and the previous solutions are the initial
 * guess. Halfway the pools are copied (a checkpoint) and the copy, reopened with
 * dk_plan_open, takes the remaining steps. The same 20 steps are then run cold (each step
 * starts as the stateless call does) to show what warm starts save.
 *
 * Printed: the mesh and every step's boundary positions (bit patterns, so a test can rebuild
 * the same input in Rust), each step's iterations, the final mesh (bit patterns), and the
 * warm and cold iteration totals.
 *
 * Build: cc -std=c99 -I ffi/generated ffi/examples/plan_pitching.c libdeform_kernel.a -lm
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#define NI 48
#define NJ 16
#define N (NI * NJ)
#define B (2 * NI)
#define STEPS 20

#define CHECK(call)                                                                  \
    do {                                                                             \
        dk_status s_ = (call);                                                       \
        if (s_ != DK_OK) {                                                           \
            fprintf(stderr, "%s:%d: %s: %s\n", __FILE__, __LINE__, #call,            \
                    dk_status_str(s_));                                              \
            exit(EXIT_FAILURE);                                                      \
        }                                                                            \
    } while (0)

static void print_hex(const char *name, const double *v, size_t n) {
    size_t i;
    printf("%s", name);
    for (i = 0; i < n; i++) {
        uint64_t b;
        memcpy(&b, &v[i], sizeof b);
        printf(" %016llX", (unsigned long long)b);
    }
    printf("\n");
}

/* The wall and far-field positions at step `n`: the wall turned by the pitch angle about the
 * quarter chord (x = -0.25), the far field fixed. */
static void boundary_at(int n, const double *points, const uint32_t *boundary, double *deformed) {
    const double amplitude = 5.0 * 3.14159265358979323846 / 180.0;
    double frac = n <= STEPS / 2 ? (double)n / (STEPS / 2) : (double)(STEPS - n) / (STEPS / 2);
    double a = -amplitude * frac, c = cos(a), s = sin(a);
    int k;
    for (k = 0; k < B; k++) {
        const double *p = &points[2 * boundary[k]];
        if (k < NI) {
            double x = p[0] + 0.25, y = p[1];
            deformed[2 * k] = -0.25 + (c * x - s * y);
            deformed[2 * k + 1] = s * x + c * y;
        } else {
            deformed[2 * k] = p[0];
            deformed[2 * k + 1] = p[1];
        }
    }
}

/* Steps the plan in `plan` through steps `from..=to`; returns the total iterations; the mesh
 * of the last step is in `out`. */
static size_t steps(const dk_plan_pools *plan, const double *points, const uint32_t *boundary,
                    uint32_t start, int from, int to, int print, double *out) {
    static double deformed[2 * B];
    size_t total = 0;
    int n;
    for (n = from; n <= to; n++) {
        dk_plan_step_report r;
        boundary_at(n, points, boundary, deformed);
        CHECK(dk_plan_step(plan, 2, deformed, 2 * B, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, start,
                           out, 2 * N, &r));
        if (!r.converged || r.step != (uint64_t)n) {
            fprintf(stderr, "step %d did not converge\n", n);
            exit(EXIT_FAILURE);
        }
        total += r.iterations;
        if (print) {
            char name[32];
            sprintf(name, "step %d deformed", n);
            print_hex(name, deformed, 2 * B);
            printf("step %d iterations %zu warm %d extrapolated %d\n", n, r.iterations, r.warm,
                   r.extrapolated);
        }
    }
    return total;
}

int main(void) {
    static double points[2 * N], out[2 * N];
    static uint32_t cell_offsets[NI * (NJ - 1) + 1], cell_nodes[4 * NI * (NJ - 1)];
    static uint8_t cell_kinds[NI * (NJ - 1)];
    static uint32_t offsets[N + 1], *targets;
    static uint32_t boundary[B], element_offsets[B + 1], element_nodes[2 * B];
    static uint8_t element_kinds[B];
    /* The cells, as the graph builder takes them (filled below; the struct only borrows). */
    const dk_cells cells = {.offsets = cell_offsets,
                            .offsets_len = NI * (NJ - 1) + 1,
                            .nodes = cell_nodes,
                            .nodes_len = 4 * NI * (NJ - 1),
                            .kinds = cell_kinds,
                            .kinds_len = NI * (NJ - 1)};
    size_t targets_len, used_targets, total_warm, total_cold;
    dk_plan_options options;
    dk_plan_sizes work, pools;
    dk_plan_info info;
    double *work_reals, *reals;
    uint32_t *work_indices, *indices;
    uint8_t *work_bytes, *bytes;
    int i, j, c = 0;

    /* O-grid: ring 0 is the wall (an ellipse, chord 1, thickness 0.12), ring NJ-1 the far
     * field (radius 10); rings clustered towards the wall. */
    for (j = 0; j < NJ; j++) {
        double s = (double)j / (NJ - 1), w = s * s * s;
        for (i = 0; i < NI; i++) {
            double t = 2.0 * 3.14159265358979323846 * i / NI;
            double wx = 0.5 * cos(t), wy = 0.06 * sin(t);
            double fx = 10.0 * cos(t), fy = 10.0 * sin(t);
            points[2 * (j * NI + i)] = (1.0 - w) * wx + w * fx;
            points[2 * (j * NI + i) + 1] = (1.0 - w) * wy + w * fy;
        }
    }
    for (j = 0; j + 1 < NJ; j++) {
        for (i = 0; i < NI; i++) {
            uint32_t i1 = (uint32_t)((i + 1) % NI);
            cell_offsets[c] = (uint32_t)(4 * c);
            cell_nodes[4 * c] = (uint32_t)(j * NI + i);
            cell_nodes[4 * c + 1] = (uint32_t)(j * NI) + i1;
            cell_nodes[4 * c + 2] = (uint32_t)((j + 1) * NI) + i1;
            cell_nodes[4 * c + 3] = (uint32_t)((j + 1) * NI + i);
            cell_kinds[c] = 9; /* VTK quadrilateral */
            c++;
        }
    }
    cell_offsets[c] = (uint32_t)(4 * c);
    CHECK(dk_graph_from_cells_len(N, &cells, 0, NULL, 0, true, &targets_len));
    targets = malloc(targets_len * sizeof *targets);
    if (!targets) return EXIT_FAILURE;
    CHECK(dk_graph_from_cells(N, &cells, 0, NULL, 0, true, offsets, N + 1, targets, targets_len,
                              &used_targets));

    /* Boundary: the wall ring, then the far-field ring; segments over 0..B on each. */
    for (i = 0; i < NI; i++) {
        boundary[i] = (uint32_t)i;
        boundary[NI + i] = (uint32_t)((NJ - 1) * NI + i);
    }
    for (i = 0; i < B; i++) {
        int ring = i / NI, k = i % NI;
        element_offsets[i] = (uint32_t)(2 * i);
        element_nodes[2 * i] = (uint32_t)(ring * NI + k);
        element_nodes[2 * i + 1] = (uint32_t)(ring * NI + (k + 1) % NI);
        element_kinds[i] = 3; /* VTK line segment */
    }
    element_offsets[B] = 2 * B;
    print_hex("points", points, 2 * N);

    /* The mesh a plan is built from: points, spring graph, boundary nodes and their segments
     * (the quaternion method takes the rotations from their shape); no stiffness given, so
     * Batina's from the options. */
    const dk_plan_mesh mesh = {.points = points,
                               .points_len = 2 * N,
                               .graph = {.offsets = offsets,
                                         .offsets_len = N + 1,
                                         .targets = targets,
                                         .targets_len = used_targets},
                               .boundary = boundary,
                               .boundary_len = B,
                               .elements = {.offsets = element_offsets,
                                            .offsets_len = B + 1,
                                            .nodes = element_nodes,
                                            .nodes_len = 2 * B,
                                            .kinds = element_kinds,
                                            .kinds_len = B}};

    /* Set up once: work sizes, pool sizes, init (the work buffers are freed after). */
    CHECK(dk_plan_options_default(&options));
    CHECK(dk_plan_work_sizes(&mesh, 2, &options, &work));
    work_reals = malloc((work.reals + 1) * sizeof *work_reals);
    work_indices = malloc((work.indices + 1) * sizeof *work_indices);
    work_bytes = malloc(work.bytes + 1);
    if (!work_reals || !work_indices || !work_bytes) return EXIT_FAILURE;
    const dk_plan_pools scratch = {.reals = work_reals,
                                   .reals_len = work.reals,
                                   .indices = work_indices,
                                   .indices_len = work.indices,
                                   .bytes = work_bytes,
                                   .bytes_len = work.bytes};
    CHECK(dk_plan_pool_sizes(&mesh, 2, &options, &scratch, &pools));
    reals = malloc(pools.reals * sizeof *reals);
    indices = malloc(pools.indices * sizeof *indices);
    bytes = malloc(pools.bytes);
    if (!reals || !indices || !bytes) return EXIT_FAILURE;
    /* The plan's three pools: init writes them, every step reads and updates them. */
    const dk_plan_pools plan = {.reals = reals,
                                .reals_len = pools.reals,
                                .indices = indices,
                                .indices_len = pools.indices,
                                .bytes = bytes,
                                .bytes_len = pools.bytes};
    CHECK(dk_plan_init(&mesh, 2, &options, &scratch, &plan, &info));
    printf("plan: %zu nodes, %zu boundary points, %zu multigrid levels, pools %zu + %zu + %zu\n",
           info.nodes, info.boundary, info.amg_levels, info.used.reals, info.used.indices,
           info.used.bytes);

    total_warm = steps(&plan, points, boundary, DK_PLAN_WARM, 1, STEPS / 2, 1, out);
    {
        /* A checkpoint halfway: the pools hold no pointers, so a copy is a plan. */
        double *r2 = malloc(info.used.reals * sizeof *r2);
        uint32_t *i2 = malloc(info.used.indices * sizeof *i2);
        uint8_t *b2 = malloc(info.used.bytes);
        const dk_plan_pools checkpoint = {.reals = r2,
                                          .reals_len = info.used.reals,
                                          .indices = i2,
                                          .indices_len = info.used.indices,
                                          .bytes = b2,
                                          .bytes_len = info.used.bytes};
        dk_plan_info copy;
        if (!r2 || !i2 || !b2) return EXIT_FAILURE;
        memcpy(r2, reals, info.used.reals * sizeof *r2);
        memcpy(i2, indices, info.used.indices * sizeof *i2);
        memcpy(b2, bytes, info.used.bytes);
        memset(reals, 0xff, info.used.reals * sizeof *reals); /* the original is gone */
        if (dk_plan_open(&plan, 2, &copy) != DK_ERR_BAD_PLAN) {
            fprintf(stderr, "an overwritten plan was accepted\n");
            return EXIT_FAILURE;
        }
        CHECK(dk_plan_open(&checkpoint, 2, &copy));
        if (copy.steps != STEPS / 2) return EXIT_FAILURE;
        total_warm += steps(&checkpoint, points, boundary, DK_PLAN_WARM, STEPS / 2 + 1, STEPS, 1,
                            out);
        free(r2);
        free(i2);
        free(b2);
    }
    print_hex("final", out, 2 * N);

    /* The same steps from cold starts, in a fresh plan. */
    CHECK(dk_plan_init(&mesh, 2, &options, &scratch, &plan, &info));
    total_cold = steps(&plan, points, boundary, DK_PLAN_COLD, 1, STEPS, 0, out);
    printf("iterations: warm %zu, cold %zu\n", total_warm, total_cold);

    free(targets);
    free(work_reals);
    free(work_indices);
    free(work_bytes);
    free(reals);
    free(indices);
    free(bytes);
    return total_warm < total_cold ? EXIT_SUCCESS : EXIT_FAILURE;
}

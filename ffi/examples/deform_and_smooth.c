/* deform-kernel from C: quaternion mesh deformation of a structured O-grid around an elliptic
 * body that pitches and plunges, propagated by inverse-distance weighting (rotations from the
 * boundary shape), by transfinite interpolation (per-node rotations) and by linear springs on
 * the grid's edge graph, then Taubin smoothing of the deformed grid's radial lines. Prints every result's bit pattern so the test harness
 * can compare it with the Rust API and with the Fortran example, bit for bit.
 *
 * The grid is built with + - * / only (a rational parametrisation of the circle), so C,
 * Fortran and Rust generate the same bits.
 *
 * Build: cc -std=c99 -I ffi/generated deform_and_smooth.c ffi/capi/target/release/libdeform_kernel.a -lm */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#define NI 24        /* points around the body (i), a multiple of 4 */
#define NJ 12        /* points from the wall to the far field (j) */
#define N (NI * NJ)  /* mesh nodes */
#define NB (2 * NI)  /* boundary nodes: the wall (j = 0) and the far field (j = NJ - 1) */
#define NC (NI * (NJ - 1)) /* quadrilateral cells */
#define SCRATCH (40 * N)   /* >= every scratch length queried below */
#define EDGES (8 * NC)     /* the edge graph's targets length bound: 8 per quad */

#define CHECK(call)                                                                  \
    do {                                                                             \
        dk_status s_ = (call);                                                       \
        if (s_ != DK_OK) {                                                           \
            fprintf(stderr, "%s failed: %s\n", #call, dk_status_str((int32_t)s_));   \
            exit(EXIT_FAILURE);                                                      \
        }                                                                            \
    } while (0)

static void print_f64(const char *name, const double *v, size_t n) {
    size_t i;
    printf("%s", name);
    for (i = 0; i < n; i++) {
        unsigned long long bits;
        memcpy(&bits, &v[i], sizeof bits);
        printf(" %016llX", bits);
    }
    printf("\n");
}

static void print_f32(const char *name, const float *v, size_t n) {
    size_t i;
    printf("%s", name);
    for (i = 0; i < n; i++) {
        uint32_t bits;
        memcpy(&bits, &v[i], sizeof bits);
        printf(" %08X", (unsigned)bits);
    }
    printf("\n");
}

/* The O-grid: point (i, j) at index i + NI j, 2 scalars each. The unit circle is
 * (1 - t^2, 2 t) / (1 + t^2), t in [0, 1) per quadrant; the wall is the ellipse
 * (x, 0.4 y), the far field the circle of radius 8, and grid line j sits at (j / (NJ - 1))^2
 * of the way out (clustered at the wall). */
static void make_grid(double *points) {
    const int m = NI / 4;
    int i, j;
    for (j = 0; j < NJ; j++) {
        double f = (double)j / (double)(NJ - 1);
        double s = f * f;
        for (i = 0; i < NI; i++) {
            double t = (double)(i % m) / (double)m;
            double c = (1.0 - t * t) / (1.0 + t * t);
            double d = (2.0 * t) / (1.0 + t * t);
            double cx, cy, wx, wy, fx, fy;
            switch (i / m) {
            case 0: cx = c; cy = d; break;
            case 1: cx = -d; cy = c; break;
            case 2: cx = -c; cy = -d; break;
            default: cx = d; cy = -c; break;
            }
            wx = cx;
            wy = 0.4 * cy;
            fx = 8.0 * cx;
            fy = 8.0 * cy;
            points[2 * (i + NI * j)] = wx + s * (fx - wx);
            points[2 * (i + NI * j) + 1] = wy + s * (fy - wy);
        }
    }
}

int main(void) {
    static double points[2 * N], out[2 * N], translations[2 * N], rotations[4 * N];
    static double scratch[SCRATCH], deformed[2 * NB], node_rot[4 * NB];
    static float points32[2 * N], out32[2 * N], translations32[2 * N], rotations32[4 * N];
    static float scratch32[SCRATCH], deformed32[2 * NB], node_rot32[4 * NB];
    static double values[SCRATCH], stiffness[EDGES], tfi[2 * N];
    static float values32[SCRATCH], stiffness32[EDGES];
    static uint32_t cell_offsets[NC + 1], cell_nodes[4 * NC], offsets[N + 1], targets[EDGES];
    static uint32_t index_scratch[N + 5 * NB];
    static uint8_t cell_kinds[NC], fixed[N];
    /* The cells, as the graph builder takes them (filled below; the struct only borrows). */
    const dk_cells cells = {.offsets = cell_offsets,
                            .offsets_len = NC + 1,
                            .nodes = cell_nodes,
                            .nodes_len = 4 * NC,
                            .kinds = cell_kinds,
                            .kinds_len = NC};
    size_t targets_len, values_len;
    dk_spring_solve_options options;
    dk_spring_solve_report spring_report;
    uint32_t nodes[NB], element_offsets[NB + 1], element_nodes[2 * NB];
    uint8_t element_kinds[NB];
    /* The boundary segments (filled below), as the motions take them. */
    const dk_cells segments = {.offsets = element_offsets,
                               .offsets_len = NB + 1,
                               .nodes = element_nodes,
                               .nodes_len = 2 * NB,
                               .kinds = element_kinds,
                               .kinds_len = NB};
    double axis[3] = {0.0, 0.0, 1.0}, q[4], wall[2 * NI], turned[2 * NI], origin[2];
    const double pivot[2] = {0.25, 0.0}, shift[2] = {0.05, 0.1};
    size_t len, k;
    dk_boundary_motion motion;
    dk_boundary_motion_f32 motion32;
    dk_smooth_arclength_options smooth;
    dk_smooth_report report;

    make_grid(points);
    for (k = 0; k < 2 * N; k++) points32[k] = (float)points[k];

    /* The boundary: wall nodes first, then the far field; its segments in boundary numbering,
     * each loop in the same (counter-clockwise) order. */
    for (k = 0; k < NI; k++) {
        nodes[k] = (uint32_t)k;
        nodes[NI + k] = (uint32_t)(NI * (NJ - 1) + k);
    }
    for (k = 0; k < NB; k++) {
        size_t loop = k / NI * NI;
        element_offsets[k] = (uint32_t)(2 * k);
        element_nodes[2 * k] = (uint32_t)k;
        element_nodes[2 * k + 1] = (uint32_t)(loop + (k + 1) % NI);
        element_kinds[k] = 3; /* VTK line */
    }
    element_offsets[NB] = 2 * NB;

    /* The grid's quadrilaterals (periodic in i), their edge graph, Batina's stiffness 1/|d|
     * and the fixed mask (exactly the boundary nodes) for the spring propagation. */
    for (k = 0; k < NC; k++) {
        size_t i = k % NI, j = k / NI;
        cell_offsets[k] = (uint32_t)(4 * k);
        cell_nodes[4 * k] = (uint32_t)(i + NI * j);
        cell_nodes[4 * k + 1] = (uint32_t)((i + 1) % NI + NI * j);
        cell_nodes[4 * k + 2] = (uint32_t)((i + 1) % NI + NI * (j + 1));
        cell_nodes[4 * k + 3] = (uint32_t)(i + NI * (j + 1));
        cell_kinds[k] = 9; /* VTK quad */
    }
    cell_offsets[NC] = 4 * NC;
    CHECK(dk_graph_from_cells_len(N, &cells, 0, NULL, 0, false, &len));
    if (len > EDGES) return EXIT_FAILURE;
    CHECK(dk_graph_from_cells(N, &cells, 0, NULL, 0, false, offsets, N + 1, targets, len,
                              &targets_len));
    /* The graph, and the spring system of each precision built on it: declared once, passed to
     * every call that needs them. */
    const dk_graph graph = {.offsets = offsets,
                            .offsets_len = N + 1,
                            .targets = targets,
                            .targets_len = targets_len};
    const dk_spring_system system = {.graph = graph,
                                     .stiffness = stiffness,
                                     .stiffness_len = targets_len,
                                     .fixed = fixed,
                                     .fixed_len = N};
    const dk_spring_system_f32 system32 = {.graph = graph,
                                           .stiffness = stiffness32,
                                           .stiffness_len = targets_len,
                                           .fixed = fixed,
                                           .fixed_len = N};
    CHECK(dk_spring_batina_stiffness(&graph, points, 2 * N, 2, 1.0, stiffness, targets_len));
    CHECK(dk_spring_batina_stiffness_f32(&graph, points32, 2 * N, 2, 1.0f, stiffness32,
                                         targets_len));
    for (k = 0; k < N; k++) fixed[k] = 0;
    for (k = 0; k < NB; k++) fixed[nodes[k]] = 1;

    /* The motion: the wall pitches by 0.15 rad about the pivot and plunges by the shift; the far
     * field stays put. */
    CHECK(dk_quat_from_axis_angle(axis, 0.15, q));
    for (k = 0; k < 2 * NI; k++) wall[k] = points[k] - pivot[k % 2];
    CHECK(dk_quat_rotate_points_2d(q, wall, 2 * NI, turned, 2 * NI));
    for (k = 0; k < NI; k++) {
        deformed[2 * k] = (turned[2 * k] + pivot[0]) + shift[0];
        deformed[2 * k + 1] = (turned[2 * k + 1] + pivot[1]) + shift[1];
        deformed[2 * (NI + k)] = points[2 * nodes[NI + k]];
        deformed[2 * (NI + k) + 1] = points[2 * nodes[NI + k] + 1];
        memcpy(&node_rot[4 * k], q, sizeof q);
        node_rot[4 * (NI + k)] = 1.0;
        node_rot[4 * (NI + k) + 1] = 0.0;
        node_rot[4 * (NI + k) + 2] = 0.0;
        node_rot[4 * (NI + k) + 3] = 0.0;
    }
    for (k = 0; k < 2 * NB; k++) deformed32[k] = (float)deformed[k];
    for (k = 0; k < 4 * NB; k++) node_rot32[k] = (float)node_rot[k];

    /* 1. Inverse-distance weighting, rotations from the boundary shape, default origin. */
    CHECK(dk_deform_idw_scratch_len(N, NB, 2, &len));
    if (len > SCRATCH) return EXIT_FAILURE;
    CHECK(dk_boundary_motion_default(&motion));
    motion.nodes = nodes;
    motion.nodes_len = NB;
    motion.deformed = deformed;
    motion.deformed_len = 2 * NB;
    motion.elements = segments;
    motion.rotation_source = DK_ROTATIONS_SHAPE;
    CHECK(dk_deform_idw(points, 2 * N, 2, &motion, 3.0, scratch, len, NULL, 0, translations,
                        2 * N, rotations, 4 * N, out, 2 * N, origin, 2));
    print_f64("idw_origin", origin, 2);
    print_f64("idw", out, 2 * N);

    /* 2. Transfinite interpolation along j, per-node rotations, origin at the pivot. */
    CHECK(dk_deform_tfi_scratch_len(NI, NJ, 1, NB, 2, &len));
    if (len > SCRATCH) return EXIT_FAILURE;
    motion.rotation_source = DK_ROTATIONS_PER_NODE;
    motion.node_rotations = node_rot;
    motion.node_rotations_len = 4 * NB;
    motion.has_origin = 1;
    motion.origin[0] = pivot[0];
    motion.origin[1] = pivot[1];
    CHECK(dk_deform_tfi(NI, NJ, 1, DK_DIRECTION_J, points, 2 * N, 2, &motion, scratch, len, NULL,
                        0, translations, 2 * N, rotations, 4 * N, tfi, 2 * N, NULL, 0));
    print_f64("tfi", tfi, 2 * N);

    /* 3. Linear springs (CG, Jacobi preconditioner), rotations from the boundary shape again. */
    motion.rotation_source = DK_ROTATIONS_SHAPE;
    motion.has_origin = 0;
    CHECK(dk_spring_solve_options_default(&options));
    CHECK(dk_deform_spring_scratch_len(N, NB, 2, &options, &len, &values_len));
    if (len > SCRATCH || values_len > SCRATCH) return EXIT_FAILURE;
    CHECK(dk_deform_spring(points, 2 * N, 2, &motion, &system, &options, scratch, len, values,
                           values_len, index_scratch, N, translations, 2 * N, rotations, 4 * N,
                           out, 2 * N, origin, 2, &spring_report));
    print_f64("spring_origin", origin, 2);
    print_f64("spring", out, 2 * N);
    printf("spring_converged %d\n", spring_report.converged ? 1 : 0);

    /* 4. Taubin smoothing of the TFI grid's radial lines (normalised arclength, both ends
     * fixed). */
    CHECK(dk_smooth_arclength_options_default(1, &smooth));
    smooth.normalised = 1;
    smooth.iterations = 10;
    CHECK(dk_taubin_smooth_arclength_scratch_len(NI, NJ, 1, &smooth, 2, &len));
    if (len > SCRATCH) return EXIT_FAILURE;
    CHECK(dk_taubin_smooth_arclength(NI, NJ, 1, &smooth, tfi, 2 * N, 2, scratch, len, &report));
    print_f64("smoothed", tfi, 2 * N);
    printf("smooth_iterations %u\n", (unsigned)report.iterations);

    /* The same three steps in single precision. */
    CHECK(dk_deform_idw_scratch_len(N, NB, 2, &len));
    CHECK(dk_boundary_motion_default_f32(&motion32));
    motion32.nodes = nodes;
    motion32.nodes_len = NB;
    motion32.deformed = deformed32;
    motion32.deformed_len = 2 * NB;
    motion32.elements = segments;
    CHECK(dk_deform_idw_f32(points32, 2 * N, 2, &motion32, 3.0f, scratch32, len, NULL, 0,
                            translations32, 2 * N, rotations32, 4 * N, out32, 2 * N, NULL, 0));
    print_f32("idw_f32", out32, 2 * N);

    CHECK(dk_deform_tfi_scratch_len(NI, NJ, 1, NB, 2, &len));
    motion32.rotation_source = DK_ROTATIONS_PER_NODE;
    motion32.node_rotations = node_rot32;
    motion32.node_rotations_len = 4 * NB;
    motion32.has_origin = 1;
    motion32.origin[0] = (float)pivot[0];
    motion32.origin[1] = (float)pivot[1];
    CHECK(dk_deform_tfi_f32(NI, NJ, 1, DK_DIRECTION_J, points32, 2 * N, 2, &motion32, scratch32,
                            len, NULL, 0, translations32, 2 * N, rotations32, 4 * N, out32, 2 * N,
                            NULL, 0));
    print_f32("tfi_f32", out32, 2 * N);

    CHECK(dk_taubin_smooth_arclength_scratch_len(NI, NJ, 1, &smooth, 2, &len));
    CHECK(dk_taubin_smooth_arclength_f32(NI, NJ, 1, &smooth, out32, 2 * N, 2, scratch32, len,
                                         &report));
    print_f32("smoothed_f32", out32, 2 * N);

    motion32.rotation_source = DK_ROTATIONS_SHAPE;
    motion32.has_origin = 0;
    CHECK(dk_spring_solve_options_default_f32(&options));
    CHECK(dk_deform_spring_scratch_len(N, NB, 2, &options, &len, &values_len));
    CHECK(dk_deform_spring_f32(points32, 2 * N, 2, &motion32, &system32, &options, scratch32,
                               len, values32, values_len, index_scratch, N, translations32, 2 * N,
                               rotations32, 4 * N, out32, 2 * N, NULL, 0, &spring_report));
    print_f32("spring_f32", out32, 2 * N);
    return EXIT_SUCCESS;
}

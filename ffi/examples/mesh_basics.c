/* deform-kernel from C: the edge graph of a small quad mesh, a rotation of its points, and the
 * quaternion tools. Prints every result's bit pattern so the test harness can compare it with
 * the Rust API and with the Fortran example, bit for bit.
 *
 * Build: cc -std=c99 -I ffi/generated mesh_basics.c ffi/capi/target/release/libdeform_kernel.a -lm */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#define CHECK(call)                                                                  \
    do {                                                                             \
        dk_status s_ = (call);                                                       \
        if (s_ != DK_OK) {                                                           \
            fprintf(stderr, "%s failed: %s\n", #call, dk_status_str((int32_t)s_));   \
            return EXIT_FAILURE;                                                     \
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

int main(void) {
    /* A 3 x 3 grid of points (z = 0) and its four quads, 0-based. */
    double points[27];
    float points32[27];
    const uint32_t cell_offsets[5] = {0, 4, 8, 12, 16};
    const uint32_t cell_nodes[16] = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7};
    const uint8_t cell_kinds[4] = {9, 9, 9, 9};
    /* The cells as the kernel takes them: each array with its length, in one struct. */
    const dk_cells cells = {.offsets = cell_offsets,
                            .offsets_len = 5,
                            .nodes = cell_nodes,
                            .nodes_len = 16,
                            .kinds = cell_kinds,
                            .kinds_len = 4};
    uint32_t offsets[10];
    uint32_t targets[64];
    size_t targets_len = 0, used = 0, i;
    double axis[3] = {0.0, 0.0, 1.0}, q[4], rotated[27], arc[4], mid[4], avg[4];
    const double from[3] = {1.0, 0.0, 0.0}, to[3] = {0.0, 1.0, 0.5};
    float axis32[3] = {0.0f, 0.0f, 1.0f}, q32[4], rotated32[27], plane32[18], turned32[18];

    for (i = 0; i < 9; i++) {
        points[3 * i] = (double)(i % 3) * 0.5;
        points[3 * i + 1] = (double)(i / 3) * 0.25;
        points[3 * i + 2] = 0.0;
        points32[3 * i] = (float)points[3 * i];
        points32[3 * i + 1] = (float)points[3 * i + 1];
        points32[3 * i + 2] = 0.0f;
    }

    CHECK(dk_graph_from_cells_len(9, &cells, 0, NULL, 0, true, &targets_len));
    if (targets_len > sizeof targets / sizeof targets[0]) return EXIT_FAILURE;
    CHECK(dk_graph_from_cells(9, &cells, 0, NULL, 0, true, offsets, 10, targets, targets_len,
                              &used));
    printf("offsets");
    for (i = 0; i < 10; i++) printf(" %u", (unsigned)offsets[i]);
    printf("\ntargets");
    for (i = 0; i < used; i++) printf(" %u", (unsigned)targets[i]);
    printf("\n");

    CHECK(dk_quat_from_axis_angle(axis, 0.3, q));
    CHECK(dk_quat_rotate_points(q, points, 27, rotated, 27));
    print_f64("rotated", rotated, 27);

    CHECK(dk_quat_from_axis_angle_f32(axis32, 0.3f, q32));
    CHECK(dk_quat_rotate_points_f32(q32, points32, 27, rotated32, 27));
    print_f32("rotated_f32", rotated32, 27);
    /* A 2D mesh needs no z: the same rotation (about z) on (x, y) pairs. */
    for (i = 0; i < 9; i++) {
        plane32[2 * i] = points32[3 * i];
        plane32[2 * i + 1] = points32[3 * i + 1];
    }
    CHECK(dk_quat_rotate_points_2d_f32(q32, plane32, 18, turned32, 18));
    print_f32("rotated_2d_f32", turned32, 18);

    CHECK(dk_quat_rotation_arc(from, to, arc));
    print_f64("arc", arc, 4);
    CHECK(dk_quat_slerp(q, arc, 0.25, mid));
    print_f64("slerp", mid, 4);
    {
        double quats[12];
        const double weights[3] = {1.0, 2.0, 0.5};
        memcpy(quats, q, sizeof q);
        memcpy(quats + 4, arc, sizeof arc);
        for (i = 0; i < 4; i++) quats[8 + i] = -mid[i]; /* same rotation as mid */
        CHECK(dk_quat_average(quats, 12, weights, 3, avg));
        print_f64("average", avg, 4);
    }
    return EXIT_SUCCESS;
}

/* Bad input through the C ABI: every call must return its documented status and leave the
 * outputs untouched. Exits non-zero (printing the failed check) on any deviation. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "deform_kernel.h"

static int failures = 0;

#define EXPECT(call, status)                                                              \
    do {                                                                                  \
        dk_status s_ = (call);                                                            \
        if (s_ != (status)) {                                                             \
            printf("FAIL %s: got %d (%s), expected %d\n", #call, (int)s_,                 \
                   dk_status_str((int32_t)s_), (int)(status));                            \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

#define UNTOUCHED(buf, n)                                                                 \
    do {                                                                                  \
        size_t i_;                                                                        \
        for (i_ = 0; i_ < (n); i_++)                                                      \
            if ((buf)[i_] != sentinel) {                                                  \
                printf("FAIL %s[%zu] was written\n", #buf, i_);                           \
                failures++;                                                               \
                break;                                                                    \
            }                                                                             \
    } while (0)

int main(void) {
    const double sentinel = 12345.0;
    double out[4] = {sentinel, sentinel, sentinel, sentinel};
    double q[4] = {1.0, 0.0, 0.0, 0.0}, zero[4] = {0.0, 0.0, 0.0, 0.0};
    double tilted[4] = {0.9, 0.1, 0.0, 0.3};
    double nanq[4] = {NAN, 0.0, 0.0, 0.0}, axis0[3] = {0.0, 0.0, 0.0};
    double pts[6] = {1, 2, 3, 4, 5, 6}, pout[6];
    const uint32_t edges[4] = {0, 1, 1, 5};
    const uint32_t edges1[4] = {1, 2, 2, 3}; /* 1-based */
    uint32_t iscr[8]; /* index_scratch for the 1-based calls */
    const uint32_t loop_edges[2] = {2, 2};
    uint32_t offsets[4] = {7, 7, 7, 7}, targets[4] = {7, 7, 7, 7};
    size_t used = 99, i;
    const uint32_t co[2] = {0, 4}, cn[4] = {0, 1, 2, 3};
    const uint8_t bad_kind[1] = {42};
    const uint8_t quad[1] = {9};

    EXPECT(dk_quat_mul(NULL, q, out), DK_ERR_NULL_POINTER);
    EXPECT(dk_quat_mul(q, q, NULL), DK_ERR_NULL_POINTER);
    EXPECT(dk_quat_normalize(zero, out), DK_ERR_ZERO_LENGTH);
    EXPECT(dk_quat_normalize(nanq, out), DK_ERR_NON_FINITE);
    EXPECT(dk_quat_mul(nanq, q, out), DK_ERR_NON_FINITE);
    EXPECT(dk_quat_inverse(zero, out), DK_ERR_ZERO_LENGTH);
    EXPECT(dk_quat_from_axis_angle(axis0, 1.0, out), DK_ERR_ZERO_LENGTH);
    EXPECT(dk_quat_from_axis_angle(q, NAN, out), DK_ERR_NON_FINITE);
    EXPECT(dk_quat_slerp(q, q, NAN, out), DK_ERR_NON_FINITE);
    EXPECT(dk_quat_average(zero, 4, NULL, 0, out), DK_ERR_ZERO_LENGTH);
    EXPECT(dk_quat_average(q, 3, NULL, 0, out), DK_ERR_LENGTH_MISMATCH);
    UNTOUCHED(out, 4);

    for (i = 0; i < 6; i++) pout[i] = sentinel;
    EXPECT(dk_quat_rotate_points(q, pts, 5, pout, 5), DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_quat_rotate_points(q, pts, 6, pout, 3), DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_quat_rotate_points(q, NULL, 6, pout, 6), DK_ERR_NULL_POINTER);
    EXPECT(dk_quat_rotate_points_2d(q, pts, 5, pout, 5), DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_quat_rotate_points_2d(tilted, pts, 6, pout, 6), DK_ERR_INVALID_PARAMETER);
    pts[4] = INFINITY;
    EXPECT(dk_quat_rotate_points(q, pts, 6, pout, 6), DK_ERR_NON_FINITE);
    EXPECT(dk_quat_rotate_points_2d(q, pts, 6, pout, 6), DK_ERR_NON_FINITE);
    UNTOUCHED(pout, 6);

    EXPECT(dk_graph_from_edges(3, edges, 4, 0, NULL, 0, offsets, 4, targets, 4, &used),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(dk_graph_from_edges(3, edges, 3, 0, NULL, 0, offsets, 4, targets, 4, &used),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_graph_from_edges(3, edges1, 4, 2, iscr, 8, offsets, 4, targets, 4, &used),
           DK_ERR_BAD_INDEX_BASE);
    EXPECT(dk_graph_from_edges(3, edges1, 4, 0, NULL, 0, offsets, 4, targets, 4, &used),
           DK_ERR_INDEX_OUT_OF_RANGE); /* 3 is out of range when read 0-based */
    EXPECT(dk_graph_from_edges(3, edges, 2, 0, NULL, 0, offsets, 3, targets, 4, &used),
           DK_ERR_LENGTH_MISMATCH); /* offsets must have node_count + 1 entries */
    EXPECT(dk_graph_from_edges(3, edges1, 4, 1, iscr, 8, offsets, 4, targets, 3, &used),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(dk_graph_from_edges(3, loop_edges, 2, 0, NULL, 0, offsets, 4, targets, 4, &used),
           DK_ERR_SELF_LOOP);
    EXPECT(dk_graph_from_edges(3, edges1, 4, 1, iscr, 8, NULL, 4, targets, 4, &used),
           DK_ERR_NULL_POINTER);
    EXPECT(dk_graph_from_edges(3, edges1, 4, 1, iscr, 8, offsets, 4, targets, 4, NULL),
           DK_ERR_NULL_POINTER);
    EXPECT(dk_graph_from_edges(3, edges1, 4, 1, iscr, 3, offsets, 4, targets, 4, &used),
           DK_ERR_BUFFER_TOO_SMALL); /* 1-based needs edges_len index_scratch entries */
    EXPECT(dk_graph_from_edges(3, edges1, 4, 1, NULL, 0, offsets, 4, targets, 4, &used),
           DK_ERR_BUFFER_TOO_SMALL);
    for (i = 0; i < 4; i++)
        if (offsets[i] != 7 || targets[i] != 7) {
            printf("FAIL graph buffers were written\n");
            failures++;
            break;
        }
    if (used != 99) {
        printf("FAIL used_out was written\n");
        failures++;
    }

    EXPECT(dk_cells_check(4, co, 2, cn, 4, bad_kind, 1, 0, NULL, 0), DK_ERR_UNKNOWN_CELL_KIND);
    EXPECT(dk_cells_check(3, co, 2, cn, 4, quad, 1, 0, NULL, 0), DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(dk_cells_check(4, co, 2, cn, 3, quad, 1, 0, NULL, 0), DK_ERR_BAD_OFFSETS);
    EXPECT(dk_cells_check(4, co, 2, cn, 4, quad, 1, 1, iscr, 8),
           DK_ERR_BAD_OFFSETS); /* 0 is not 1-based */
    EXPECT(dk_cells_check(4, co, 2, cn, 4, quad, 1, 1, iscr, 5),
           DK_ERR_BUFFER_TOO_SMALL); /* 1-based needs offsets + nodes = 6 entries */
    EXPECT(dk_cells_check(4, co, 2, cn, 4, quad, 1, 0, NULL, 0), DK_OK);
    EXPECT(dk_graph_check(offsets, 4, targets, 0, false), DK_ERR_BAD_OFFSETS);

    if (strcmp(dk_status_str(DK_OK), "success") != 0 || dk_status_str(-7) == NULL) {
        printf("FAIL dk_status_str\n");
        failures++;
    }
    if (failures == 0)
        printf("bad_input: every check held\n");
    else
        printf("bad_input: %d checks failed\n", failures);
    return failures == 0 ? 0 : 1;
}

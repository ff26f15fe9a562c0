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
    const dk_cells one_quad = {co, 2, cn, 4, quad, 1};
    dk_cells cells;
    const dk_graph no_edges = {offsets, 4, targets, 0};
    double values[3] = {0.0, 1.0, 2.0}, residual = sentinel;
    float values32[3] = {0.0f, 1.0f, 2.0f}, residual32 = 12345.0f;
    dk_plan_options plan_options;
    dk_plan_sizes sizes = {99, 99, 99};
    dk_plan_info info, info0;
    dk_plan_step_report step_report, step_report0;

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

    cells = one_quad;
    cells.kinds = bad_kind;
    EXPECT(dk_cells_check(4, &cells, 0, NULL, 0), DK_ERR_UNKNOWN_CELL_KIND);
    EXPECT(dk_cells_check(3, &one_quad, 0, NULL, 0), DK_ERR_INDEX_OUT_OF_RANGE);
    cells = one_quad;
    cells.nodes_len = 3;
    EXPECT(dk_cells_check(4, &cells, 0, NULL, 0), DK_ERR_BAD_OFFSETS);
    EXPECT(dk_cells_check(4, &one_quad, 1, iscr, 8),
           DK_ERR_BAD_OFFSETS); /* 0 is not 1-based */
    EXPECT(dk_cells_check(4, &one_quad, 1, iscr, 5),
           DK_ERR_BUFFER_TOO_SMALL); /* 1-based needs offsets + nodes = 6 entries */
    EXPECT(dk_cells_check(4, &one_quad, 0, NULL, 0), DK_OK);
    EXPECT(dk_graph_check(&no_edges, false), DK_ERR_BAD_OFFSETS);

    /* A NULL parameter struct, of every kind, is DK_ERR_NULL_POINTER and writes nothing. */
    EXPECT(dk_graph_check(NULL, false), DK_ERR_NULL_POINTER);
    EXPECT(dk_cells_check(4, NULL, 0, NULL, 0), DK_ERR_NULL_POINTER);
    EXPECT(dk_spring_relative_residual(NULL, 1, values, 3, NULL, 0, &residual),
           DK_ERR_NULL_POINTER);
    EXPECT(dk_spring_relative_residual_f32(NULL, 1, values32, 3, NULL, 0, &residual32),
           DK_ERR_NULL_POINTER);
    if (residual != sentinel || residual32 != 12345.0f) {
        printf("FAIL residual_out was written\n");
        failures++;
    }
    EXPECT(dk_plan_options_default(&plan_options), DK_OK);
    EXPECT(dk_plan_work_sizes(NULL, 2, &plan_options, &sizes), DK_ERR_NULL_POINTER);
    EXPECT(dk_plan_work_sizes_f32(NULL, 2, &plan_options, &sizes), DK_ERR_NULL_POINTER);
    if (sizes.reals != 99 || sizes.indices != 99 || sizes.bytes != 99) {
        printf("FAIL sizes_out was written\n");
        failures++;
    }
    memset(&info, 0x5a, sizeof info);
    memcpy(&info0, &info, sizeof info);
    memset(&step_report, 0x5a, sizeof step_report);
    memcpy(&step_report0, &step_report, sizeof step_report);
    EXPECT(dk_plan_open(NULL, 2, &info), DK_ERR_NULL_POINTER);
    EXPECT(dk_plan_open_f32(NULL, 2, &info), DK_ERR_NULL_POINTER);
    EXPECT(dk_plan_step(NULL, 2, zero, 2, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, DK_PLAN_WARM,
                        pout, 6, &step_report),
           DK_ERR_NULL_POINTER);
    if (memcmp(&info, &info0, sizeof info) != 0 ||
        memcmp(&step_report, &step_report0, sizeof step_report) != 0) {
        printf("FAIL a plan output was written\n");
        failures++;
    }
    UNTOUCHED(pout, 6);

    /* The partitioned IDW and prolongator: a NULL partition or exchange is refused at once
     * (no callback called), nothing written. */
    {
        size_t lens[4] = {99, 99, 99, 99}, counts[2] = {99, 99};
        dk_partitioned_motion motion;
        uint32_t p_offsets[2] = {7, 7};
        uint64_t p_columns[2] = {7, 7};
        double p_values[2] = {sentinel, sentinel};
        memset(&motion, 0, sizeof motion);
        EXPECT(dk_partitioned_deform_idw_lens(NULL, 2, 4, 4, lens), DK_ERR_NULL_POINTER);
        EXPECT(dk_partitioned_prolongator_lens(NULL, &one_quad, false, lens),
               DK_ERR_NULL_POINTER);
        for (i = 0; i < 4; i++)
            if (lens[i] != 99) {
                printf("FAIL lens_out was written\n");
                failures++;
                break;
            }
        EXPECT(dk_partitioned_deform_idw(NULL, pts, 6, 3, 2.0, &motion, NULL, 0, NULL, 0, NULL,
                                         0, NULL, 0, NULL, 0, NULL, pout, 6, NULL, 0),
               DK_ERR_NULL_POINTER);
        UNTOUCHED(pout, 6);
        EXPECT(dk_partitioned_prolongator(NULL, &one_quad, false, pts, 6, 3, 1.0, NULL, 0, NULL,
                                          0, NULL, 0, NULL, 0, NULL, p_offsets, 2, p_columns, 2,
                                          p_values, 2, counts),
               DK_ERR_NULL_POINTER);
        UNTOUCHED(p_values, 2);
        if (p_offsets[0] != 7 || p_columns[0] != 7 || counts[0] != 99 || counts[1] != 99) {
            printf("FAIL a prolongator output was written\n");
            failures++;
        }
    }

    /* The sliding sensitivities: a NULL struct (system, constraints, cells, graph) or a bad
     * dim is refused, nothing written. */
    {
        double dx[2] = {sentinel, sentinel}, g[2] = {sentinel, sentinel}, w2[2] = {0.0, 0.0};
        float dx32[2] = {12345.0f, 12345.0f}, g32[2] = {12345.0f, 12345.0f}, w32[2] = {0, 0};
        float p32[2] = {0, 0};
        size_t len = 99;
        dk_spring_solve_options so;
        dk_elasticity_options eo;
        dk_spring_solve_report rep, rep0;
        EXPECT(dk_spring_solve_options_default(&so), DK_OK);
        EXPECT(dk_elasticity_options_default(&eo), DK_OK);
        memset(&rep, 0x5a, sizeof rep);
        memcpy(&rep0, &rep, sizeof rep);
        EXPECT(dk_sensitivity_spring_sliding_adjoint_scratch_len(4, 5, &so, &len),
               DK_ERR_INVALID_PARAMETER);
        EXPECT(dk_elasticity_sliding_sensitivity_scratch_len(4, 1, 4, 0, &len),
               DK_ERR_INVALID_PARAMETER);
        if (len != 99) {
            printf("FAIL len_out was written\n");
            failures++;
        }
        EXPECT(dk_sensitivity_spring_sliding_tangent(NULL, NULL, &so, 2, dx, 2, NULL, 0, NULL, 0,
                                                     &rep),
               DK_ERR_NULL_POINTER);
        EXPECT(dk_sensitivity_spring_sliding_tangent_f32(NULL, NULL, &so, 2, dx32, 2, NULL, 0,
                                                         NULL, 0, &rep),
               DK_ERR_NULL_POINTER);
        EXPECT(dk_sensitivity_spring_sliding_adjoint(NULL, NULL, &so, 2, w2, 2, g, 2, NULL, 0,
                                                     NULL, 0, &rep),
               DK_ERR_NULL_POINTER);
        EXPECT(dk_sensitivity_spring_sliding_adjoint_f32(NULL, NULL, &so, 7, w32, 2, g32, 2, NULL,
                                                         0, NULL, 0, &rep),
               DK_ERR_INVALID_PARAMETER);
        EXPECT(dk_elasticity_sliding_tangent(&one_quad, 0, NULL, 0, NULL, 2, NULL, 0, NULL, &eo,
                                             NULL, 0, w2, 2, dx, 2, NULL, 0, &rep),
               DK_ERR_NULL_POINTER);
        EXPECT(dk_elasticity_sliding_tangent_f32(NULL, 0, NULL, 0, NULL, 2, NULL, 0, NULL, &eo,
                                                 NULL, 0, p32, 2, dx32, 2, NULL, 0, &rep),
               DK_ERR_NULL_POINTER);
        EXPECT(dk_elasticity_sliding_adjoint(NULL, 0, NULL, 0, NULL, 2, NULL, 0, NULL, &eo, NULL,
                                             0, pts, 2, w2, 2, g, 2, NULL, 0, &rep),
               DK_ERR_NULL_POINTER);
        EXPECT(dk_elasticity_sliding_adjoint_f32(NULL, 0, NULL, 0, NULL, 2, NULL, 0, NULL, &eo,
                                                 NULL, 0, p32, 2, w32, 2, g32, 2, NULL, 0, NULL),
               DK_ERR_NULL_POINTER);
        UNTOUCHED(dx, 2);
        UNTOUCHED(g, 2);
        if (dx32[0] != 12345.0f || dx32[1] != 12345.0f || g32[0] != 12345.0f ||
            memcmp(&rep, &rep0, sizeof rep) != 0) {
            printf("FAIL a sliding sensitivity output was written\n");
            failures++;
        }
    }

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

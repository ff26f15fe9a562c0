/* Plans from C: the f32 twins on a small mesh, and bad input (documented status, nothing
 * written). Prints "plan: every check held" when every check holds. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#define NX 5
#define N (NX * NX)
#define B (4 * (NX - 1))

static int failures = 0;
#define EXPECT(cond)                                                        \
    do {                                                                    \
        if (!(cond)) {                                                      \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
            failures++;                                                     \
        }                                                                   \
    } while (0)

int main(void) {
    static float points[2 * N], out[2 * N], before[2 * N], deformed[2 * B];
    static uint32_t cell_offsets[(NX - 1) * (NX - 1) + 1], cell_nodes[4 * (NX - 1) * (NX - 1)];
    static uint8_t cell_kinds[(NX - 1) * (NX - 1)];
    static uint32_t offsets[N + 1], targets[8 * N], boundary[B];
    size_t targets_len, used, k;
    dk_plan_options options;
    dk_plan_sizes work, pools;
    dk_plan_info info, info2;
    dk_plan_step_report report, untouched;
    dk_cells cells;
    dk_plan_mesh_f32 mesh;            /* the mesh the plan is built from */
    dk_plan_pools_f32 scratch, plan;  /* init's work buffers; the plan's pools */
    dk_plan_pools_f32 short_plan;     /* the pools with one scalar too few */
    float *wr, *reals;
    uint32_t *wi, *indices;
    uint8_t *wb, *bytes;
    int i, j, c = 0, b = 0;

    for (j = 0; j < NX; j++)
        for (i = 0; i < NX; i++) {
            points[2 * (j * NX + i)] = (float)i;
            points[2 * (j * NX + i) + 1] = (float)j;
        }
    for (j = 0; j + 1 < NX; j++)
        for (i = 0; i + 1 < NX; i++) {
            cell_offsets[c] = (uint32_t)(4 * c);
            cell_nodes[4 * c] = (uint32_t)(j * NX + i);
            cell_nodes[4 * c + 1] = (uint32_t)(j * NX + i + 1);
            cell_nodes[4 * c + 2] = (uint32_t)((j + 1) * NX + i + 1);
            cell_nodes[4 * c + 3] = (uint32_t)((j + 1) * NX + i);
            cell_kinds[c] = 9; /* VTK quadrilateral */
            c++;
        }
    cell_offsets[c] = (uint32_t)(4 * c);
    cells = (dk_cells){cell_offsets, (size_t)c + 1, cell_nodes, 4 * (size_t)c, cell_kinds,
                       (size_t)c};
    if (dk_graph_from_cells_len(N, &cells, 0, NULL, 0, true, &targets_len) != DK_OK ||
        targets_len > sizeof targets / sizeof targets[0] ||
        dk_graph_from_cells(N, &cells, 0, NULL, 0, true, offsets, N + 1, targets, targets_len,
                            &used) != DK_OK)
        return EXIT_FAILURE;
    /* The perimeter is the boundary; the top row moves up by 0.5. */
    for (j = 0; j < NX; j++)
        for (i = 0; i < NX; i++)
            if (i == 0 || j == 0 || i == NX - 1 || j == NX - 1) {
                int n = j * NX + i;
                boundary[b] = (uint32_t)n;
                deformed[2 * b] = points[2 * n];
                deformed[2 * b + 1] = points[2 * n + 1] + (j == NX - 1 ? 0.5f : 0.0f);
                b++;
            }
    /* No boundary elements, no stiffness (Batina's from the options). */
    mesh = (dk_plan_mesh_f32){.points = points,
                              .points_len = 2 * N,
                              .graph = {offsets, N + 1, targets, used},
                              .boundary = boundary,
                              .boundary_len = B};

    /* f32 spring plan with a one-level solver. */
    EXPECT(dk_plan_options_default_f32(&options) == DK_OK);
    EXPECT(options.method == DK_PLAN_QUATERNION && options.solver == DK_PLAN_SOLVER_AMG);
    options.method = DK_PLAN_SPRING;
    options.solver = DK_PLAN_SOLVER_LINEAR;
    EXPECT(dk_plan_work_sizes_f32(&mesh, 2, &options, &work) == DK_OK);
    wr = malloc((work.reals + 1) * sizeof *wr);
    wi = malloc((work.indices + 1) * sizeof *wi);
    wb = malloc(work.bytes + 1);
    if (!wr || !wi || !wb) return EXIT_FAILURE;
    scratch = (dk_plan_pools_f32){wr, work.reals, wi, work.indices, wb, work.bytes};
    EXPECT(dk_plan_pool_sizes_f32(&mesh, 2, &options, &scratch, &pools) == DK_OK);
    reals = malloc(pools.reals * sizeof *reals);
    indices = malloc(pools.indices * sizeof *indices);
    bytes = malloc(pools.bytes);
    if (!reals || !indices || !bytes) return EXIT_FAILURE;
    plan = (dk_plan_pools_f32){reals, pools.reals, indices, pools.indices, bytes, pools.bytes};
    short_plan = plan;
    short_plan.reals_len--;

    /* Bad input at init: dimension, a repeated boundary node, a short pool; nothing written. */
    memset(&info, 0x5a, sizeof info);
    memcpy(&info2, &info, sizeof info);
    EXPECT(dk_plan_init_f32(&mesh, 4, &options, &scratch, &plan, &info) ==
           DK_ERR_INVALID_PARAMETER);
    boundary[1] = boundary[0];
    EXPECT(dk_plan_init_f32(&mesh, 2, &options, &scratch, &plan, &info) == DK_ERR_DUPLICATE_NODE);
    boundary[1] = 1;
    EXPECT(dk_plan_init_f32(&mesh, 2, &options, &scratch, &short_plan, &info) ==
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(memcmp(&info, &info2, sizeof info) == 0);

    EXPECT(dk_plan_init_f32(&mesh, 2, &options, &scratch, &plan, &info) == DK_OK);
    EXPECT(info.nodes == N && info.boundary == B && info.steps == 0 && info.amg_levels == 0 &&
           info.method == DK_PLAN_SPRING);
    EXPECT(dk_plan_open_f32(&plan, 2, &info2) == DK_OK);
    EXPECT(memcmp(&info, &info2, sizeof info) == 0);

    /* Bad input at a step: wrong lengths, start code, dimension; out and the plan unchanged. */
    for (k = 0; k < 2 * N; k++) out[k] = -7.0f;
    memcpy(before, out, sizeof out);
    memset(&untouched, 0x5a, sizeof untouched);
    memcpy(&report, &untouched, sizeof report);
    EXPECT(dk_plan_step_f32(&plan, 2, deformed, 2 * B - 2, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0,
                            DK_PLAN_WARM, out, 2 * N, &report) == DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_plan_step_f32(&plan, 2, deformed, 2 * B, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0, 7,
                            out, 2 * N, &report) == DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_plan_step_f32(&plan, 3, deformed, 2 * B, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0,
                            DK_PLAN_WARM, out, 2 * N, &report) == DK_ERR_BAD_PLAN);
    /* Empty pools (every array NULL, length 0) hold no plan. */
    EXPECT(dk_plan_step(&(dk_plan_pools){0}, 2, NULL, 0, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0,
                        DK_PLAN_WARM, NULL, 0, &report) == DK_ERR_BAD_PLAN);
    EXPECT(memcmp(out, before, sizeof out) == 0);
    EXPECT(memcmp(&report, &untouched, sizeof report) == 0);

    /* A good step: converged, the boundary exactly where it was put, interior moved up. */
    EXPECT(dk_plan_step_f32(&plan, 2, deformed, 2 * B, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0,
                            DK_PLAN_WARM, out, 2 * N, &report) == DK_OK);
    EXPECT(report.converged && report.step == 1 && !report.warm);
    for (k = 0; k < B; k++) {
        EXPECT(out[2 * boundary[k]] == deformed[2 * k]);
        EXPECT(out[2 * boundary[k] + 1] == deformed[2 * k + 1]);
    }
    EXPECT(out[2 * (2 * NX + 2) + 1] > 2.0f && out[2 * (2 * NX + 2) + 1] < 2.5f);

    /* A given stiffness (Batina's, computed by the caller) gives the first step's bits; a
     * stiffness of the wrong length and bad multigrid options are refused. */
    {
        static float k[8 * N], out2[2 * N];
        dk_plan_sizes pools2;
        dk_plan_info info3;
        dk_plan_mesh_f32 stiff_mesh = mesh; /* the same mesh with the stiffness k */
        dk_plan_pools_f32 plan2;
        float *r2;
        uint32_t *i2;
        uint8_t *b2;
        EXPECT(dk_spring_batina_stiffness_f32(&mesh.graph, points, 2 * N, 2, 1.0f, k, used) ==
               DK_OK);
        stiff_mesh.stiffness = k;
        stiff_mesh.stiffness_len = used;
        EXPECT(dk_plan_pool_sizes_f32(&stiff_mesh, 2, &options, &scratch, &pools2) == DK_OK);
        r2 = malloc(pools2.reals * sizeof *r2);
        i2 = malloc(pools2.indices * sizeof *i2);
        b2 = malloc(pools2.bytes);
        if (!r2 || !i2 || !b2) return EXIT_FAILURE;
        plan2 = (dk_plan_pools_f32){r2, pools2.reals, i2, pools2.indices, b2, pools2.bytes};
        memset(&info3, 0x5a, sizeof info3);
        memcpy(&info2, &info3, sizeof info3);
        stiff_mesh.stiffness_len = used - 1;
        EXPECT(dk_plan_init_f32(&stiff_mesh, 2, &options, &scratch, &plan2, &info3) ==
               DK_ERR_LENGTH_MISMATCH);
        stiff_mesh.stiffness_len = used;
        options.solver = DK_PLAN_SOLVER_AMG;
        options.amg.smoother = 7;
        EXPECT(dk_plan_init_f32(&stiff_mesh, 2, &options, &scratch, &plan2, &info3) ==
               DK_ERR_INVALID_PARAMETER);
        options.amg.smoother = DK_AMG_CHEBYSHEV;
        options.amg.max_coarse = 0;
        EXPECT(dk_plan_init_f32(&stiff_mesh, 2, &options, &scratch, &plan2, &info3) ==
               DK_ERR_INVALID_PARAMETER);
        EXPECT(memcmp(&info3, &info2, sizeof info3) == 0);
        options.solver = DK_PLAN_SOLVER_LINEAR;
        EXPECT(dk_plan_init_f32(&stiff_mesh, 2, &options, &scratch, &plan2, &info3) == DK_OK);
        EXPECT(dk_plan_step_f32(&plan2, 2, deformed, 2 * B, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0,
                                DK_PLAN_WARM, out2, 2 * N, &report) == DK_OK);
        EXPECT(memcmp(out, out2, sizeof out) == 0);
        free(r2);
        free(i2);
        free(b2);
    }

    /* An overwritten immutable part is refused, and the stored state is not touched. */
    reals[0] += 1.0f;
    memcpy(before, out, sizeof out);
    EXPECT(dk_plan_step_f32(&plan, 2, deformed, 2 * B, DK_ROTATIONS_SHAPE, NULL, 0, NULL, 0,
                            DK_PLAN_WARM, out, 2 * N, &report) == DK_ERR_BAD_PLAN);
    EXPECT(memcmp(out, before, sizeof out) == 0);
    EXPECT(dk_plan_open_f32(&plan, 2, &info2) == DK_ERR_BAD_PLAN);
    reals[0] -= 1.0f;
    EXPECT(dk_plan_open_f32(&plan, 2, &info2) == DK_OK);
    EXPECT(info2.steps == 1);

    free(wr);
    free(wi);
    free(wb);
    free(reals);
    free(indices);
    free(bytes);
    if (failures) return EXIT_FAILURE;
    printf("plan: every check held\n");
    return EXIT_SUCCESS;
}

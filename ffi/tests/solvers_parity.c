/* Bit parity of the solver ABI with the Rust API: prints the bits of a linear spring solve,
 * a structured Taubin smoothing, an Alter arclength smoothing and a graph smoothing, in f64
 * and f32. host-tests/tests/ffi/c_abi_solvers.rs computes the same with deform_kernel and
 * compares the text. */
#include <stdio.h>
#include <stdint.h>
#include <string.h>

#include "deform_kernel.h"

/* hex64, hex32 */
#define DK_TEST_PRINTERS_ONLY
#include "check.h"

static int failed = 0;

static void check(dk_status s, const char *what) {
    if (s != DK_OK) {
        printf("FAIL %s: %s\n", what, dk_status_str((int32_t)s));
        failed = 1;
    }
}


/* 4 x 4 grid graph, node i + 4 j. */
static uint32_t goff[17], gtgt[48];
static const dk_graph grid_graph = {goff, 17, gtgt, 48};
/* chain 0 - 1 - 2 - 3 - 4 */
static uint32_t coff[6], ctgt[8];
static const dk_graph chain_graph = {coff, 6, ctgt, 8};

static void graphs(void) {
    uint32_t e[64];
    size_t k = 0, i, j, used;
    for (j = 0; j < 4; j++)
        for (i = 0; i < 4; i++) {
            if (i + 1 < 4) {
                e[k++] = (uint32_t)(i + 4 * j);
                e[k++] = (uint32_t)(i + 1 + 4 * j);
            }
            if (j + 1 < 4) {
                e[k++] = (uint32_t)(i + 4 * j);
                e[k++] = (uint32_t)(i + 4 * (j + 1));
            }
        }
    check(dk_graph_from_edges(16, e, k, 0, NULL, 0, goff, 17, gtgt, 48, &used), "grid");
    for (k = 0, i = 0; i < 4; i++) {
        e[k++] = (uint32_t)i;
        e[k++] = (uint32_t)(i + 1);
    }
    check(dk_graph_from_edges(5, e, k, 0, NULL, 0, coff, 6, ctgt, 8, &used), "chain");
}

#define BODY(REAL, FN, HEX, TAG)                                                          \
    do {                                                                                  \
        REAL pts[32], k[48], v[16], s[80], field[60], fs[60], grid[36], gs[64], gv[10];   \
        REAL lambda, mu, cs[10];                                                          \
        uint8_t fixed[16];                                                                \
        uint32_t idx[16];                                                                 \
        const FN(dk_spring_system) sys = {grid_graph, k, 48, fixed, 16};                  \
        dk_spring_solve_options so;                                                       \
        dk_spring_solve_report sr;                                                        \
        dk_structured_options st;                                                         \
        dk_filter_report fr;                                                              \
        dk_smooth_arclength_options ao;                                                   \
        dk_smooth_report ar;                                                              \
        size_t i, j, need;                                                                \
        static const double xs[6] = {0, 1, 2, 3, 6, 9};                                   \
        for (j = 0; j < 4; j++)                                                           \
            for (i = 0; i < 4; i++) {                                                     \
                size_t n = i + 4 * j;                                                     \
                pts[2 * n] = (REAL)((double)i + 0.1 * (double)(j * j));                   \
                pts[2 * n + 1] = (REAL)((double)j + 0.05 * (double)(i * i));              \
                fixed[n] = (uint8_t)(i == 0 || j == 0 || i == 3 || j == 3);              \
                v[n] = fixed[n] ? (REAL)((double)((n * 5) % 7) / 7.0) : 0;                \
            }                                                                             \
        check(FN(dk_spring_batina_stiffness)(&grid_graph, pts, 32, 2, 1, k, 48),          \
              "batina");                                                                  \
        check(FN(dk_spring_solve_options_default)(&so), "options");                       \
        check(FN(dk_spring_solve_linear)(&sys, &so, 1, v, 16, s, 80, idx, 16, &sr),       \
              "solve");                                                                   \
        HEX("spring_" TAG, v, 16);                                                        \
        check(FN(dk_taubin_params_paper)(&lambda, &mu), "paper");                         \
        for (i = 0; i < 60; i++) field[i] = (REAL)((double)((i * 7919) % 13) / 13.0);     \
        memset(&st, 0, sizeof st);                                                        \
        check(FN(dk_taubin_smooth_structured)(5, 4, 3, lambda, mu, 5, &st, field, 60, fs, \
                                              60, &fr),                                   \
              "structured");                                                              \
        HEX("structured_" TAG, field, 60);                                                \
        for (j = 0; j < 3; j++)                                                           \
            for (i = 0; i < 6; i++) {                                                     \
                grid[2 * (i + 6 * j)] = (REAL)(xs[i] + 0.25 * (double)j);                 \
                grid[2 * (i + 6 * j) + 1] = (REAL)j;                                      \
            }                                                                             \
        check(dk_smooth_arclength_options_default(0, &ao), "defaults");                   \
        ao.normalised = 1;                                                                \
        check(dk_taubin_smooth_arclength_scratch_len(6, 3, 1, &ao, 2, &need), "len");     \
        check(FN(dk_taubin_smooth_arclength)(6, 3, 1, &ao, grid, 36, 2, gs, need, &ar),   \
              "arclength");                                                               \
        HEX("arclength_" TAG, grid, 36);                                                  \
        for (i = 0; i < 10; i++) gv[i] = (REAL)((double)((i * 37) % 11) / 11.0);          \
        check(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 0, NULL, 0, lambda, mu, 3,   \
                                         2, gv, 10, cs, 10, &fr),                         \
              "graph");                                                                   \
        HEX("graph_" TAG, gv, 10);                                                        \
    } while (0)

#define F64(name) name
#define F32(name) name##_f32

/* The angle-spring scratch lengths of the 4 x 4 grid (2D), for the three methods with
 * epsilon 0.01 and 0: the Rust test compares them with deform_kernel's angle_scratch_len. */
static void angle_scratch(void) {
    dk_spring_angle_options o;
    size_t need, m, e;
    printf("angle_scratch");
    for (e = 0; e < 2; e++)
        for (m = 0; m < 3; m++) {
            check(dk_spring_angle_options_default(&o), "angle defaults");
            o.method = (uint32_t)m;
            o.epsilon = e ? 0.0 : 0.01;
            check(dk_spring_solve_angle_scratch_len(16, 2, &o, &need), "angle len");
            printf(" %zu", need);
            check(dk_spring_solve_angle_scratch_len_f32(16, 2, &o, &need), "angle len f32");
            printf(" %zu", need);
        }
    printf("\n");
}

int main(void) {
    graphs();
    angle_scratch();
    BODY(double, F64, hex64, "f64");
    BODY(float, F32, hex32, "f32");
    return failed;
}

/* A C solver that owns part of a mesh and moves it with the kernel under MPI, with the
 * serial bits for any number of processes (issue 16, the protocol in ffi/README.md).
 *
 *   mpicc -std=c11 -O2 -Iffi/generated ffi/examples/mpi_deform.c libdeform_kernel.a -lm -lpthread -ldl
 *   mpirun -np 3 ./a.out
 *
 * The mesh: an nx × ny grid of quads (graph edges along both grid directions and one
 * diagonal per cell). The boundary is prescribed: the left and right edges are fixed, the
 * bottom and top edges are sheared. The interior follows by linear-spring Jacobi sweeps.
 *
 * Rank r owns the grid rows j with j % size == r: an arbitrary, interleaved set of nodes, as
 * a solver's own partition would be. Every sweep:
 *   1. each rank sweeps its own rows with dk_spring_jacobi_sweep_exact (one call per row: the
 *      kernel reads the neighbours' values from the whole field, halo included);
 *   2. the ranks exchange their new values (MPI_Allgatherv; a real solver would send only
 *      the halo rows);
 *   3. the exact residual words of all calls and ranks are added element-wise
 *      (MPI_Allreduce, MPI_SUM on MPI_INT64_T) and rounded once with dk_exact_sum_value;
 *      the maximum change is merged with MPI_MAX.
 * The stopping decision uses only merged values, so every rank takes it at the same sweep.
 * Rank 0 then runs the same sweeps serially (one range: all nodes) and compares every value
 * and every sweep's residual bit for bit. Exit status 0 only if all are identical.
 */
#include <mpi.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

enum { NX = 41, NY = 29, COMPONENTS = 2, MAX_SWEEPS = 5000 };

#define CHECK(call)                                                                        \
    do {                                                                                   \
        dk_status s_ = (call);                                                             \
        if (s_ != DK_OK) {                                                                 \
            fprintf(stderr, "%s failed: %s\n", #call, dk_status_str(s_));            \
            MPI_Abort(MPI_COMM_WORLD, 2);                                                  \
        }                                                                                  \
    } while (0)

static size_t node(int i, int j) { return (size_t)j * NX + (size_t)i; }

/* The problem every rank builds identically. */
typedef struct {
    size_t n;
    dk_spring_system system; /* graph, stiffness, fixed mask: built once, used by every sweep */
    uint32_t *scratch;
    double *x0;
} problem;

static void build(problem *p) {
    size_t n = (size_t)NX * NY;
    size_t cells = (size_t)(NX - 1) * (NY - 1);
    size_t edges_len = 2 * ((size_t)(NX - 1) * NY + (size_t)NX * (NY - 1) + cells);
    uint32_t *edges = malloc(edges_len * sizeof *edges);
    size_t e = 0;
    for (int j = 0; j < NY; j++)
        for (int i = 0; i < NX; i++) {
            if (i + 1 < NX) { edges[e++] = (uint32_t)node(i, j); edges[e++] = (uint32_t)node(i + 1, j); }
            if (j + 1 < NY) { edges[e++] = (uint32_t)node(i, j); edges[e++] = (uint32_t)node(i, j + 1); }
            if (i + 1 < NX && j + 1 < NY) { edges[e++] = (uint32_t)node(i, j); edges[e++] = (uint32_t)node(i + 1, j + 1); }
        }
    size_t tlen = 0;
    CHECK(dk_graph_from_edges_len(e, &tlen));
    p->n = n;
    uint32_t *offsets = malloc((n + 1) * sizeof *offsets);
    uint32_t *targets = malloc(tlen * sizeof *targets);
    size_t used = 0;
    CHECK(dk_graph_from_edges(n, edges, e, 0, NULL, 0, offsets, n + 1, targets, tlen, &used));
    free(edges);
    const dk_graph graph = {.offsets = offsets,
                            .offsets_len = n + 1,
                            .targets = targets,
                            .targets_len = used};
    /* A slightly irregular grid, so the stiffness varies from edge to edge. */
    double *points = malloc(2 * n * sizeof *points);
    for (int j = 0; j < NY; j++)
        for (int i = 0; i < NX; i++) {
            double x = i / (double)(NX - 1), y = j / (double)(NY - 1);
            points[2 * node(i, j)] = x + 0.01 * x * (1 - x) * y;
            points[2 * node(i, j) + 1] = y * (1 + 0.3 * x * x);
        }
    double *stiffness = malloc(used * sizeof *stiffness);
    CHECK(dk_spring_batina_stiffness(&graph, points, 2 * n, 2, 1.0, stiffness, used));
    uint8_t *fixed = calloc(n, 1);
    p->system = (dk_spring_system){.graph = graph,
                                   .stiffness = stiffness,
                                   .stiffness_len = used,
                                   .fixed = fixed,
                                   .fixed_len = n};
    p->x0 = calloc(COMPONENTS * n, sizeof *p->x0);
    for (int j = 0; j < NY; j++)
        for (int i = 0; i < NX; i++) {
            size_t k = node(i, j);
            int edge = i == 0 || i == NX - 1 || j == 0 || j == NY - 1;
            if (!edge) continue;
            fixed[k] = 1;
            double x = points[2 * k], y = points[2 * k + 1];
            if (j == 0 || j == NY - 1) { /* sheared bottom and top */
                p->x0[COMPONENTS * k] = 0.05 * y * x * (1 - x);
                p->x0[COMPONENTS * k + 1] = 0.02 * x;
            }
        }
    free(points);
    size_t slen = 0;
    CHECK(dk_spring_index_scratch_len(n, &slen));
    p->scratch = malloc(slen * sizeof *p->scratch);
}

/* One sweep over `rows` (grid rows) from src to dst; returns the merged residual words. */
static void sweep_rows(const problem *p, const int *rows, int nrows, const double *src,
                       double *dst, int64_t words[DK_EXACT_SUM_WORDS], double *max_change) {
    memset(words, 0, DK_EXACT_SUM_WORDS * sizeof *words);
    *max_change = 0;
    size_t slen = p->n;
    for (int r = 0; r < nrows; r++) {
        size_t start = node(0, rows[r]), end = start + NX;
        dk_spring_sweep s;
        int64_t w[DK_EXACT_SUM_WORDS];
        CHECK(dk_spring_jacobi_sweep_exact(&p->system, start, end, 0, COMPONENTS, src,
                                           COMPONENTS * p->n, dst, COMPONENTS * p->n, p->scratch,
                                           slen, &s, w));
        for (int k = 0; k < DK_EXACT_SUM_WORDS; k++) words[k] += w[k];
        if (s.max_change > *max_change) *max_change = s.max_change;
    }
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    problem p;
    build(&p);
    size_t n = p.n, len = COMPONENTS * n;

    /* This rank's rows, and every rank's, in the order MPI_Allgatherv delivers them. */
    int *mine = malloc(NY * sizeof *mine), nmine = 0;
    for (int j = rank; j < NY; j += size) mine[nmine++] = j;
    int *counts = malloc(size * sizeof *counts), *displs = malloc(size * sizeof *displs);
    int *order = malloc(NY * sizeof *order), total = 0;
    for (int r = 0; r < size; r++) {
        displs[r] = total * NX * COMPONENTS;
        int c = 0;
        for (int j = r; j < NY; j += size) order[total + c++] = j;
        counts[r] = c * NX * COMPONENTS;
        total += c;
    }

    double *x = malloc(len * sizeof *x), *next = malloc(len * sizeof *next);
    double *send = malloc((size_t)nmine * NX * COMPONENTS * sizeof *send);
    double *recv = malloc(len * sizeof *recv);
    memcpy(x, p.x0, len * sizeof *x);
    memcpy(next, p.x0, len * sizeof *next);
    double residuals[MAX_SWEEPS];
    int sweeps = 0;
    double first = -1;
    for (; sweeps < MAX_SWEEPS; sweeps++) {
        int64_t words[DK_EXACT_SUM_WORDS], global[DK_EXACT_SUM_WORDS];
        double local_max, max_change, residual_sq;
        sweep_rows(&p, mine, nmine, x, next, words, &local_max);
        for (int r = 0; r < nmine; r++)
            memcpy(send + (size_t)r * NX * COMPONENTS, next + node(0, mine[r]) * COMPONENTS,
                   NX * COMPONENTS * sizeof *send);
        MPI_Allgatherv(send, nmine * NX * COMPONENTS, MPI_DOUBLE, recv, counts, displs,
                       MPI_DOUBLE, MPI_COMM_WORLD);
        for (int r = 0; r < NY; r++)
            memcpy(x + node(0, order[r]) * COMPONENTS, recv + (size_t)r * NX * COMPONENTS,
                   NX * COMPONENTS * sizeof *x);
        MPI_Allreduce(words, global, DK_EXACT_SUM_WORDS, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
        MPI_Allreduce(&local_max, &max_change, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        CHECK(dk_exact_sum_value(global, &residual_sq));
        residuals[sweeps] = residual_sq;
        if (first < 0) first = residual_sq;
        /* Same merged numbers on every rank: the same decision everywhere. */
        if (residual_sq <= 1e-6 * first) { sweeps++; break; }
    }

    int ok = 1;
    if (rank == 0) {
        /* The serial run: one range over all nodes, as many sweeps. */
        double *a = malloc(len * sizeof *a), *b = malloc(len * sizeof *b);
        memcpy(a, p.x0, len * sizeof *a);
        memcpy(b, p.x0, len * sizeof *b);
        int same_residuals = 1;
        for (int s = 0; s < sweeps; s++) {
            int64_t words[DK_EXACT_SUM_WORDS];
            double residual_sq;
            /* One call over all nodes (not row by row): the split is only the other side's. */
            dk_spring_sweep sw;
            CHECK(dk_spring_jacobi_sweep_exact(&p.system, 0, n, 0, COMPONENTS, a, len, b, len,
                                               p.scratch, n, &sw, words));
            CHECK(dk_exact_sum_value(words, &residual_sq));
            same_residuals &= memcmp(&residual_sq, &residuals[s], sizeof residual_sq) == 0;
            /* The rounded per-call residual equals the exact sum's value. */
            same_residuals &= memcmp(&residual_sq, &sw.residual_sq, sizeof residual_sq) == 0;
            double *t = a; a = b; b = t;
        }
        int same_values = memcmp(a, x, len * sizeof *a) == 0;
        ok = same_values && same_residuals;
        printf("mpi_deform: %zu nodes, %d sweeps on %d rank(s) (rows interleaved): values %s, "
               "residuals %s\n",
               n, sweeps, size, same_values ? "bit-identical to serial" : "DIFFER",
               same_residuals ? "bit-identical to serial" : "DIFFER");
        free(a);
        free(b);
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Finalize();
    return ok ? 0 : 1;
}

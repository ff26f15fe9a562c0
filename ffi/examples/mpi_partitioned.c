/* A partitioned C solver moving its mesh with the kernel under MPI: each rank holds only its
 * own nodes, one layer of ghosts and the cells around them, and the answer is the serial
 * one, bit for bit, for any number of ranks (issue 27).
 *
 *   mpicc -std=c11 -O2 -Iffi/generated -Impi/c ffi/examples/mpi_partitioned.c \
 *         mpi/c/deform_kernel_mpi.c libdeform_kernel.a -lm -lpthread -ldl
 *   mpirun -np 4 ./a.out
 *
 * The mesh: an NX × NY grid of triangles around a flat plate (the nodes of row NY/2 between
 * columns PLATE0 and PLATE1), pitched by 8 degrees about its quarter chord; the outer
 * boundary stays put, the interior follows by linear springs (CG + Jacobi).
 *
 * Each rank builds its local view from the grid's formulas alone (no global array): it owns
 * the columns i with i * size / NX == rank, numbered column by column (not in global order);
 * its ghosts are the columns just left and right of them; its cells are the triangles that
 * touch an owned node; it receives each ghost column from the neighbour that owns it and
 * sends its first and last owned columns, both lists ordered by global id (j * NX + i). The
 * solve runs through the callbacks of mpi/c/deform_kernel_mpi.c (MPI_Allreduce, and
 * MPI_Isend/MPI_Irecv of the ghost columns only).
 *
 * The check (what a solver would not do): every rank also solves the whole mesh serially
 * with dk_spring_solve_linear, the owned values are gathered on rank 0 by global id and
 * compared bit for bit, and so are the iteration count and residual. Then bad inputs: a
 * duplicate global id, a ghost list one short, a failing max callback and a failing halo
 * callback are each rejected on every rank with a typed status, the values untouched.
 *
 * Then the same views move the mesh with Samareh's quaternion deformation and spring
 * propagation (dk_partitioned_deform_spring): each rank passes its owned boundary nodes (the
 * fixed ones) with their positions in the global boundary list (the fixed nodes in global id
 * order, counted from the grid's formulas) and their deformed points, and one rigid rotation
 * (the plate's pitch; the outer boundary, which stays, gets the identity). The owned deformed
 * points gathered on rank 0 equal the serial dk_deform_spring bit for bit, and so do the
 * origin and the report; a boundary count that differs on one rank and a failing max
 * callback are rejected on every rank with `out` untouched.
 * Exit status 0 only if everything holds.
 */
#include <math.h>
#include <mpi.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"
#include "deform_kernel_mpi.h"

enum { NX = 61, NY = 41, PLATE0 = 20, PLATE1 = 32, V = 2, VTK_TRIANGLE = 5 };
static const double PITCH_DEG = 8.0;

#define CHECK(call)                                                                        \
    do {                                                                                   \
        dk_status s_ = (call);                                                             \
        if (s_ != DK_OK) {                                                                 \
            fprintf(stderr, "%s failed: %s\n", #call, dk_status_str(s_));                  \
            MPI_Abort(MPI_COMM_WORLD, 2);                                                  \
        }                                                                                  \
    } while (0)

static uint64_t gid(int i, int j) { return (uint64_t)j * NX + (uint64_t)i; }

static void point(int i, int j, double p[2]) {
    double s = (double)i / (NX - 1), t = (double)j / (NY - 1);
    p[0] = -2.0 + 4.0 * s + 0.05 * sin(6.0 * t); /* mildly skewed */
    p[1] = -1.5 + 3.0 * t;
}

static int on_plate(int i, int j) { return j == NY / 2 && i >= PLATE0 && i <= PLATE1; }
static int fixed_at(int i, int j) {
    return i == 0 || j == 0 || i == NX - 1 || j == NY - 1 || on_plate(i, j);
}

/* Prescribed displacement: the plate pitched about its quarter chord, 0 elsewhere. */
static void prescribed(int i, int j, double d[2]) {
    d[0] = d[1] = 0.0;
    if (!on_plate(i, j)) return;
    double a[2], b[2], p[2];
    point(PLATE0, NY / 2, a), point(PLATE1, NY / 2, b), point(i, j, p);
    double cx = a[0] + 0.25 * (b[0] - a[0]), cy = a[1];
    double th = -PITCH_DEG * 3.14159265358979323846 / 180.0;
    double rx = p[0] - cx, ry = p[1] - cy;
    d[0] = cos(th) * rx - sin(th) * ry + cx - p[0];
    d[1] = sin(th) * rx + cos(th) * ry + cy - p[1];
}

/* The two triangles of grid quad (q, j) (columns q, q + 1), through a node numbering. */
static void quad_triangles(int q, int j, uint32_t (*num)(const void *, int, int),
                           const void *ctx, uint32_t out[6]) {
    uint32_t a = num(ctx, q, j), b = num(ctx, q + 1, j);
    uint32_t c = num(ctx, q + 1, j + 1), d = num(ctx, q, j + 1);
    uint32_t t[6] = {a, b, c, a, c, d};
    memcpy(out, t, sizeof t);
}

/* ---------------------------------------------------------------------------------------
 * One rank's local view.
 * ------------------------------------------------------------------------------------- */

typedef struct {
    int c0, c1;          /* owned columns c0 .. c1 - 1 */
    int left, right;     /* ghost columns present */
    size_t owned, local; /* node counts */
    uint64_t *ids;
    double *points;
    uint8_t *fixed;
    uint32_t ranks[2], send_off[3], recv_off[3], *send, *recv;
    uint32_t *cell_off, *cell_nodes;
    uint8_t *kinds;
    size_t cells;
    dk_partition part;
    dk_cells cellv;
} view;

static int owner(int i, int size) { return (int)((long)i * size / NX); }

/* Local number of grid node (i, j): owned column by column, then the left and right ghost
 * columns; UINT32_MAX if not local. */
static uint32_t local_of(const void *ctx, int i, int j) {
    const view *v = ctx;
    uint32_t w = (uint32_t)(v->c1 - v->c0) * NY;
    if (i >= v->c0 && i < v->c1) return (uint32_t)(i - v->c0) * NY + (uint32_t)j;
    if (v->left && i == v->c0 - 1) return w + (uint32_t)j;
    if (v->right && i == v->c1) return w + (uint32_t)(v->left ? NY : 0) + (uint32_t)j;
    return UINT32_MAX;
}

/* Appends column i (j ascending: global id order) in local numbers. */
static uint32_t *column(const view *v, int i, uint32_t *out) {
    for (int j = 0; j < NY; j++) *out++ = local_of(v, i, j);
    return out;
}

static void build_view(view *v, int rank, int size) {
    memset(v, 0, sizeof *v);
    v->c0 = 0;
    while (owner(v->c0, size) < rank) v->c0++;
    v->c1 = v->c0;
    while (v->c1 < NX && owner(v->c1, size) == rank) v->c1++;
    v->left = v->c0 > 0, v->right = v->c1 < NX;
    v->owned = (size_t)(v->c1 - v->c0) * NY;
    v->local = v->owned + (size_t)(v->left + v->right) * NY;
    v->ids = malloc(v->local * sizeof *v->ids);
    v->points = malloc(v->local * 2 * sizeof *v->points);
    v->fixed = malloc(v->local);
    for (int i = v->c0 - v->left; i < v->c1 + v->right; i++)
        for (int j = 0; j < NY; j++) {
            uint32_t l = local_of(v, i, j);
            v->ids[l] = gid(i, j);
            point(i, j, &v->points[2 * l]);
            v->fixed[l] = (uint8_t)fixed_at(i, j);
        }
    /* Neighbours: left then right; send my edge column, receive their edge column. */
    v->send = malloc(2 * NY * sizeof *v->send);
    v->recv = malloc(2 * NY * sizeof *v->recv);
    uint32_t *s = v->send, *r = v->recv;
    size_t nb = 0;
    if (v->left) {
        v->ranks[nb++] = (uint32_t)owner(v->c0 - 1, size);
        s = column(v, v->c0, s), r = column(v, v->c0 - 1, r);
        v->send_off[nb] = (uint32_t)(s - v->send), v->recv_off[nb] = (uint32_t)(r - v->recv);
    }
    if (v->right) {
        v->ranks[nb++] = (uint32_t)owner(v->c1, size);
        s = column(v, v->c1 - 1, s), r = column(v, v->c1, r);
        v->send_off[nb] = (uint32_t)(s - v->send), v->recv_off[nb] = (uint32_t)(r - v->recv);
    }
    /* Cells: both triangles of every quad touching an owned column. */
    int q0 = v->c0 - v->left, q1 = v->c1 - 1 + v->right; /* quads q0 .. q1 - 1 */
    v->cells = (size_t)(q1 - q0) * (NY - 1) * 2;
    v->cell_off = malloc((v->cells + 1) * sizeof *v->cell_off);
    v->cell_nodes = malloc(v->cells * 3 * sizeof *v->cell_nodes);
    v->kinds = malloc(v->cells);
    size_t c = 0;
    for (int q = q0; q < q1; q++)
        for (int j = 0; j < NY - 1; j++, c += 2)
            quad_triangles(q, j, local_of, v, &v->cell_nodes[3 * c]);
    for (size_t k = 0; k <= v->cells; k++) v->cell_off[k] = (uint32_t)(3 * k);
    memset(v->kinds, VTK_TRIANGLE, v->cells);
    v->part = (dk_partition){
        .rank = (uint32_t)rank, .size = (uint32_t)size, .owned = v->owned,
        .global_count = (uint64_t)NX * NY, .global_ids = v->ids, .global_ids_len = v->local,
        .neighbour_ranks = v->ranks, .neighbour_ranks_len = nb,
        .send_offsets = v->send_off, .send_offsets_len = nb + 1,
        .send = v->send, .send_len = v->send_off[nb],
        .recv_offsets = v->recv_off, .recv_offsets_len = nb + 1,
        .recv = v->recv, .recv_len = v->recv_off[nb],
    };
    v->cellv = (dk_cells){v->cell_off, v->cells + 1, v->cell_nodes, v->cells * 3,
                          v->kinds, v->cells};
}

static void free_view(view *v) {
    free(v->ids), free(v->points), free(v->fixed), free(v->send), free(v->recv);
    free(v->cell_off), free(v->cell_nodes), free(v->kinds);
}

/* Owned values: the prescribed displacement (the initial guess 0 elsewhere); ghosts any. */
static double *initial_values(const view *v) {
    double *x = malloc(v->local * V * sizeof *x);
    for (size_t l = 0; l < v->local * V; l++) x[l] = 1e300;
    for (size_t l = 0; l < v->owned; l++) {
        int i = (int)(v->ids[l] % NX), j = (int)(v->ids[l] / NX);
        prescribed(i, j, &x[V * l]);
    }
    return x;
}

/* The partitioned solve on a view with the exchange `ex`. */
static dk_status solve(const view *v, const dk_exchange *ex, double *x,
                       dk_spring_solve_report *report) {
    dk_spring_solve_options o;
    CHECK(dk_spring_solve_options_default(&o));
    size_t sl, il;
    CHECK(dk_partitioned_spring_scratch_len(&v->part, &v->cellv, false, V, &sl, &il));
    double *scratch = malloc(sl * sizeof *scratch);
    uint32_t *iscratch = malloc(il * sizeof *iscratch);
    dk_status s = dk_partitioned_spring_solve(&v->part, &v->cellv, false, v->points,
                                              v->local * 2, 2, 1.0, v->fixed, v->local, &o, V,
                                              x, v->local * V, scratch, sl, iscratch, il, ex,
                                              report);
    free(scratch), free(iscratch);
    return s;
}

/* ---------------------------------------------------------------------------------------
 * The serial reference (whole mesh, one process).
 * ------------------------------------------------------------------------------------- */

static uint32_t global_of(const void *ctx, int i, int j) {
    (void)ctx;
    return (uint32_t)gid(i, j);
}

static double *serial(dk_spring_solve_report *report) {
    size_t n = (size_t)NX * NY, cells = (size_t)(NX - 1) * (NY - 1) * 2;
    uint32_t *off = malloc((cells + 1) * sizeof *off), *nodes = malloc(cells * 3 * sizeof *nodes);
    uint8_t *kinds = malloc(cells), *fixed = malloc(n);
    double *pts = malloc(n * 2 * sizeof *pts), *x = calloc(n * V, sizeof *x);
    size_t c = 0;
    for (int q = 0; q < NX - 1; q++)
        for (int j = 0; j < NY - 1; j++, c += 2) quad_triangles(q, j, global_of, NULL, &nodes[3 * c]);
    for (size_t k = 0; k <= cells; k++) off[k] = (uint32_t)(3 * k);
    memset(kinds, VTK_TRIANGLE, cells);
    for (int j = 0; j < NY; j++)
        for (int i = 0; i < NX; i++) {
            size_t g = (size_t)gid(i, j);
            point(i, j, &pts[2 * g]);
            fixed[g] = (uint8_t)fixed_at(i, j);
            prescribed(i, j, &x[V * g]);
        }
    dk_cells cv = {off, cells + 1, nodes, cells * 3, kinds, cells};
    size_t tl, used;
    CHECK(dk_graph_from_cells_len(n, &cv, 0, NULL, 0, false, &tl));
    uint32_t *goff = malloc((n + 1) * sizeof *goff), *targets = malloc(tl * sizeof *targets);
    CHECK(dk_graph_from_cells(n, &cv, 0, NULL, 0, false, goff, n + 1, targets, tl, &used));
    dk_graph g = {goff, n + 1, targets, used};
    double *k = malloc(used * sizeof *k);
    CHECK(dk_spring_batina_stiffness(&g, pts, n * 2, 2, 1.0, k, used));
    dk_spring_system sys = {g, k, used, fixed, n};
    dk_spring_solve_options o;
    CHECK(dk_spring_solve_options_default(&o));
    size_t sl;
    CHECK(dk_spring_solve_linear_scratch_len(n, V, &o, &sl));
    double *scratch = malloc(sl * sizeof *scratch);
    uint32_t *iscratch = malloc(n * sizeof *iscratch);
    CHECK(dk_spring_solve_linear(&sys, &o, V, x, n * V, scratch, sl, iscratch, n, report));
    free(off), free(nodes), free(kinds), free(fixed), free(pts), free(goff), free(targets);
    free(k), free(scratch), free(iscratch);
    return x;
}

/* ---------------------------------------------------------------------------------------
 * Checks.
 * ------------------------------------------------------------------------------------- */

static int all(int mine) {
    int every;
    MPI_Allreduce(&mine, &every, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return every;
}

/* Gathers the owned values on rank 0 by global id; 1 on every rank when the assembled field
 * covers every node once and equals `want` bit for bit. */
static int assembled_equal(const view *v, const double *x, const double *want, int rank,
                           int size) {
    int count = (int)v->owned, *counts = malloc(size * sizeof *counts);
    int *displs = malloc(size * sizeof *displs);
    MPI_Gather(&count, 1, MPI_INT, counts, 1, MPI_INT, 0, MPI_COMM_WORLD);
    size_t n = (size_t)NX * NY, total = 0;
    if (rank == 0)
        for (int r = 0; r < size; r++) displs[r] = (int)total, total += (size_t)counts[r];
    uint64_t *ids = malloc((total + 1) * sizeof *ids);
    double *vals = malloc((total + 1) * V * sizeof *vals);
    MPI_Gatherv(v->ids, count, MPI_UINT64_T, ids, counts, displs, MPI_UINT64_T, 0,
                MPI_COMM_WORLD);
    if (rank == 0)
        for (int r = 0; r < size; r++) counts[r] *= V, displs[r] *= V;
    MPI_Gatherv(x, count * V, MPI_DOUBLE, vals, counts, displs, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    int ok = 1;
    if (rank == 0) {
        double *field = malloc(n * V * sizeof *field);
        char *seen = calloc(n, 1);
        for (size_t q = 0; q < total; q++) {
            ok &= ids[q] < n && !seen[ids[q]];
            if (ids[q] < n) seen[ids[q]] = 1, memcpy(&field[V * ids[q]], &vals[V * q], V * sizeof *vals);
        }
        ok &= total == n && memcmp(field, want, n * V * sizeof *field) == 0;
        free(field), free(seen);
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    free(counts), free(displs), free(ids), free(vals);
    return ok;
}

/* An exchange whose max or halo callback reports a failure on one rank at its k-th call,
 * after taking its part in the operation (as an MPI call returning an error code does). */
typedef struct {
    dk_exchange inner;
    int fail_rank, rank, fail_max, fail_halo, calls;
} flaky;

static int32_t flaky_sum(void *u, int64_t *w, size_t n) {
    flaky *f = u;
    return f->inner.sum_words(f->inner.user, w, n);
}
static int32_t flaky_max(void *u, double *x, size_t n) {
    flaky *f = u;
    int32_t s = f->inner.max(f->inner.user, x, n);
    return (f->fail_max && f->rank == f->fail_rank && ++f->calls == f->fail_max) ? -1 : s;
}
static int32_t flaky_halo(void *u, const dk_partition *p, double *x, size_t n, size_t w) {
    flaky *f = u;
    int32_t s = f->inner.halo(f->inner.user, p, x, n, w);
    return (f->fail_halo && f->rank == f->fail_rank && ++f->calls == f->fail_halo) ? -1 : s;
}

/* A bad case: every rank must return `want`, its values untouched. */
#define BAD_CASE(label, v, ex, want, rank) bad_case(label, v, ex, want, #want, rank)

static int bad_case(const char *label, const view *v, const dk_exchange *ex, dk_status want,
                    const char *want_name, int rank) {
    double *x = initial_values(v), *before = initial_values(v);
    dk_spring_solve_report report = {0}, blank = {0};
    dk_status s = solve(v, ex, x, &report);
    int right = s == want && memcmp(x, before, v->local * V * sizeof *x) == 0 &&
                memcmp(&report, &blank, sizeof report) == 0;
    if (!right) fprintf(stderr, "rank %d: %s: got %s\n", rank, label, dk_status_str(s));
    int ok = all(right);
    if (rank == 0)
        printf("  %-32s %s on every rank, values untouched: %s\n", label, want_name,
               ok ? "yes" : "NO");
    free(x), free(before);
    return ok;
}

static int bad_inputs(view *v, const dk_exchange *ex, int rank, int size) {
    int ok = 1, last = size - 1;
    /* A duplicate global id on the last rank. */
    uint64_t keep = v->ids[1];
    if (rank == last) v->ids[1] = v->ids[0];
    ok &= BAD_CASE("duplicate global id", v, ex, DK_ERR_BAD_PARTITION, rank);
    v->ids[1] = keep;
    /* A ghost list one short on the last rank (two ranks or more). */
    if (size > 1) {
        dk_partition p = v->part;
        if (rank == last) p.recv_len--, v->recv_off[p.recv_offsets_len - 1]--;
        view w = *v;
        w.part = p;
        ok &= BAD_CASE("ghost list one short", &w, ex, DK_ERR_BAD_PARTITION, rank);
        if (rank == last) v->recv_off[p.recv_offsets_len - 1]++;
    }
    /* Failing callbacks on rank 0: the third max, the second halo exchange. */
    flaky f = {*ex, 0, rank, 3, 0, 0};
    dk_exchange fx = {&f, flaky_sum, flaky_max, flaky_halo};
    ok &= BAD_CASE("max callback fails on rank 0", v, &fx, DK_ERR_EXCHANGE, rank);
    f.fail_max = 0, f.fail_halo = 2, f.calls = 0;
    ok &= BAD_CASE("halo callback fails on rank 0", v, &fx, DK_ERR_EXCHANGE, rank);
    return ok;
}

/* ---------------------------------------------------------------------------------------
 * The quaternion deformation on the same views.
 * ------------------------------------------------------------------------------------- */

static const double PI = 3.14159265358979323846;

/* Position of fixed node (i, j) in the global boundary list: the fixed nodes with a smaller
 * global id (rows below, then columns left in row j), from the grid's formulas. */
static uint32_t boundary_position(int i, int j) {
    uint32_t k = 0;
    for (int r = 0; r < j; r++)
        k += (r == 0 || r == NY - 1) ? NX : 2 + (r == NY / 2 ? PLATE1 - PLATE0 + 1 : 0);
    for (int c = 0; c < i; c++) k += (uint32_t)fixed_at(c, j);
    return k;
}

static uint32_t boundary_count(void) { return boundary_position(NX - 1, NY - 1) + 1; }

/* The plate's rigid pitch about its quarter chord: quaternion and origin. */
static void pitch(double q[4], double origin[3]) {
    double a[2], b[2], th = -PITCH_DEG * PI / 180.0;
    point(PLATE0, NY / 2, a), point(PLATE1, NY / 2, b);
    q[0] = cos(th / 2), q[1] = 0.0, q[2] = 0.0, q[3] = sin(th / 2);
    origin[0] = a[0] + 0.25 * (b[0] - a[0]), origin[1] = a[1], origin[2] = 0.0;
}

/* Deformed position of grid node (i, j): the point plus its prescribed displacement. */
static void deformed_at(int i, int j, double d[2]) {
    double p[2], u[2];
    point(i, j, p), prescribed(i, j, u);
    d[0] = p[0] + u[0], d[1] = p[1] + u[1];
}

/* One rank's share of the motion: its owned fixed nodes, their positions, deformed points. */
typedef struct {
    uint32_t *nodes, *positions;
    double *deformed;
    size_t len;
    dk_partitioned_motion m;
} share;

static void build_share(share *s, const view *v) {
    s->nodes = malloc((v->owned + 1) * sizeof *s->nodes);
    s->positions = malloc((v->owned + 1) * sizeof *s->positions);
    s->deformed = malloc((v->owned + 1) * 2 * sizeof *s->deformed);
    s->len = 0;
    for (size_t l = 0; l < v->owned; l++) {
        if (!v->fixed[l]) continue;
        int i = (int)(v->ids[l] % NX), j = (int)(v->ids[l] / NX);
        s->nodes[s->len] = (uint32_t)l, s->positions[s->len] = boundary_position(i, j);
        deformed_at(i, j, &s->deformed[2 * s->len]);
        s->len++;
    }
    memset(&s->m, 0, sizeof s->m);
    s->m.nodes = s->nodes, s->m.nodes_len = s->len;
    s->m.positions = s->positions, s->m.positions_len = s->len;
    s->m.deformed = s->deformed, s->m.deformed_len = 2 * s->len;
    s->m.boundary_count = boundary_count();
    s->m.rotation_source = DK_ROTATIONS_RIGID, s->m.has_origin = 1;
    pitch(s->m.rigid_rotation, s->m.origin);
}

static void free_share(share *s) { free(s->nodes), free(s->positions), free(s->deformed); }

/* The partitioned deformation of a view: `out` (owned * 2), `origin` (2), `report`. */
static dk_status deform(const view *v, const dk_partitioned_motion *m, const dk_exchange *ex,
                        double *out, double *origin, dk_spring_solve_report *report) {
    dk_spring_solve_options o;
    CHECK(dk_spring_solve_options_default(&o));
    size_t lens[4];
    CHECK(dk_partitioned_deform_spring_lens(&v->part, &v->cellv, false, 2, m->boundary_count,
                                            m->element_count, lens));
    double *scratch = malloc((lens[0] + 1) * sizeof *scratch);
    uint32_t *index = malloc((lens[1] + 1) * sizeof *index);
    int64_t *words = malloc((lens[2] + 1) * sizeof *words);
    uint8_t *kinds = malloc(lens[3] + 1);
    dk_status s = dk_partitioned_deform_spring(
        &v->part, &v->cellv, false, v->points, v->local * 2, 2, 1.0, v->fixed, v->local, m, &o,
        scratch, lens[0], index, lens[1], words, lens[2], kinds, lens[3], ex, out,
        v->owned * 2, origin, 2, report);
    free(scratch), free(index), free(words), free(kinds);
    return s;
}

/* The serial dk_deform_spring on the whole mesh: deformed points, origin, report. */
static double *serial_deform(double origin[2], dk_spring_solve_report *report) {
    size_t n = (size_t)NX * NY, cells = (size_t)(NX - 1) * (NY - 1) * 2, b = boundary_count();
    uint32_t *off = malloc((cells + 1) * sizeof *off), *nodes = malloc(cells * 3 * sizeof *nodes);
    uint8_t *kinds = malloc(cells), *fixed = malloc(n);
    double *pts = malloc(n * 2 * sizeof *pts), *out = malloc(n * 2 * sizeof *out);
    uint32_t *bnodes = malloc(b * sizeof *bnodes);
    double *bdef = malloc(b * 2 * sizeof *bdef);
    size_t c = 0, k = 0;
    for (int q = 0; q < NX - 1; q++)
        for (int j = 0; j < NY - 1; j++, c += 2) quad_triangles(q, j, global_of, NULL, &nodes[3 * c]);
    for (size_t e = 0; e <= cells; e++) off[e] = (uint32_t)(3 * e);
    memset(kinds, VTK_TRIANGLE, cells);
    for (int j = 0; j < NY; j++)
        for (int i = 0; i < NX; i++) {
            size_t g = (size_t)gid(i, j);
            point(i, j, &pts[2 * g]);
            fixed[g] = (uint8_t)fixed_at(i, j);
            if (fixed[g]) bnodes[k] = (uint32_t)g, deformed_at(i, j, &bdef[2 * k]), k++;
        }
    dk_cells cv = {off, cells + 1, nodes, cells * 3, kinds, cells};
    size_t tl, used;
    CHECK(dk_graph_from_cells_len(n, &cv, 0, NULL, 0, false, &tl));
    uint32_t *goff = malloc((n + 1) * sizeof *goff), *targets = malloc(tl * sizeof *targets);
    CHECK(dk_graph_from_cells(n, &cv, 0, NULL, 0, false, goff, n + 1, targets, tl, &used));
    dk_graph g = {goff, n + 1, targets, used};
    double *stiff = malloc(used * sizeof *stiff);
    CHECK(dk_spring_batina_stiffness(&g, pts, n * 2, 2, 1.0, stiff, used));
    dk_spring_system sys = {g, stiff, used, fixed, n};
    dk_boundary_motion m;
    CHECK(dk_boundary_motion_default(&m));
    m.nodes = bnodes, m.nodes_len = b, m.deformed = bdef, m.deformed_len = 2 * b;
    m.rotation_source = DK_ROTATIONS_RIGID, m.has_origin = 1;
    pitch(m.rigid_rotation, m.origin);
    dk_spring_solve_options o;
    CHECK(dk_spring_solve_options_default(&o));
    size_t sl, vl, il;
    CHECK(dk_deform_spring_scratch_len(n, b, 2, &o, &sl, &vl));
    CHECK(dk_deform_spring_index_scratch_len(&m, n, &il));
    double *scratch = malloc(sl * sizeof *scratch), *values = malloc(vl * sizeof *values);
    double *t = malloc(n * 2 * sizeof *t), *rot = malloc(n * 4 * sizeof *rot);
    uint32_t *iscratch = malloc((il + 1) * sizeof *iscratch);
    CHECK(dk_deform_spring(pts, n * 2, 2, &m, &sys, &o, scratch, sl, values, vl, iscratch, il,
                           t, n * 2, rot, n * 4, out, n * 2, origin, 2, report));
    free(off), free(nodes), free(kinds), free(fixed), free(pts), free(bnodes), free(bdef);
    free(goff), free(targets), free(stiff), free(scratch), free(values), free(t), free(rot);
    free(iscratch);
    return out;
}

/* A bad deformation: every rank must return `want` with `out`, origin and report untouched. */
#define BAD_DEFORM(label, v, m, ex, want, rank) bad_deform(label, v, m, ex, want, #want, rank)

static int bad_deform(const char *label, const view *v, const dk_partitioned_motion *m,
                      const dk_exchange *ex, dk_status want, const char *want_name, int rank) {
    size_t len = v->owned * 2 + 2;
    double *out = malloc(len * sizeof *out), *before = malloc(len * sizeof *before);
    for (size_t k = 0; k < len; k++) out[k] = before[k] = -1.0 - (double)k;
    dk_spring_solve_report report = {0}, blank = {0};
    dk_status s = deform(v, m, ex, out, out + v->owned * 2, &report);
    int right = s == want && memcmp(out, before, len * sizeof *out) == 0 &&
                memcmp(&report, &blank, sizeof report) == 0;
    if (!right) fprintf(stderr, "rank %d: %s: got %s\n", rank, label, dk_status_str(s));
    int ok = all(right);
    if (rank == 0)
        printf("  %-40s %s on every rank, out untouched: %s\n", label, want_name,
               ok ? "yes" : "NO");
    free(out), free(before);
    return ok;
}

/* The quaternion deformation on every rank's view against the serial one, and bad inputs. */
static int quaternion_checks(view *v, const dk_exchange *ex, int rank, int size) {
    share s;
    build_share(&s, v);
    double *out = malloc((v->owned + 1) * 2 * sizeof *out), origin[2], sorigin[2];
    dk_spring_solve_report rep, srep;
    CHECK(deform(v, &s.m, ex, out, origin, &rep));
    double *want = serial_deform(sorigin, &srep);
    int same = rep.iterations == srep.iterations && rep.converged == srep.converged &&
               memcmp(&rep.residual, &srep.residual, sizeof rep.residual) == 0 &&
               memcmp(origin, sorigin, sizeof origin) == 0;
    int ok = all(same);
    ok &= assembled_equal(v, out, want, rank, size);
    if (rank == 0)
        printf("mpi_partitioned: quaternion deformation (spring propagation), %d rank(s), "
               "B = %u, %zu CG iterations: owned points, origin and report %s the serial "
               "dk_deform_spring\n",
               size, boundary_count(), rep.iterations, ok ? "bit-identical to" : "DIFFER from");
    if (rank == 0) printf("bad inputs of the quaternion deformation:\n");
    dk_partitioned_motion m = s.m;
    if (rank == size - 1) m.boundary_count++;
    ok &= BAD_DEFORM("boundary count differs on the last rank", v, &m, ex, DK_ERR_BAD_PARTITION,
                     rank);
    flaky f = {*ex, 0, rank, 2, 0, 0};
    dk_exchange fx = {&f, flaky_sum, flaky_max, flaky_halo};
    ok &= BAD_DEFORM("max callback fails on rank 0", v, &s.m, &fx, DK_ERR_EXCHANGE, rank);
    free(out), free(want);
    free_share(&s);
    return ok;
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    dk_exchange ex;
    if (dk_mpi_exchange_new(MPI_COMM_WORLD, &ex) != MPI_SUCCESS) MPI_Abort(MPI_COMM_WORLD, 2);

    view v;
    build_view(&v, rank, size);
    double *x = initial_values(&v);
    dk_spring_solve_report rep;
    CHECK(solve(&v, &ex, x, &rep));

    dk_spring_solve_report srep;
    double *want = serial(&srep);
    int same_report = rep.iterations == srep.iterations && rep.converged == srep.converged &&
                      memcmp(&rep.residual, &srep.residual, sizeof rep.residual) == 0;
    int ok = all(same_report);
    ok &= assembled_equal(&v, x, want, rank, size);
    if (rank == 0)
        printf("mpi_partitioned: %d x %d grid, %d rank(s), %zu CG iterations, residual %.3e: "
               "assembled field %s the serial dk_spring_solve_linear\n",
               NX, NY, size, rep.iterations, rep.residual,
               ok ? "bit-identical to" : "DIFFERS from");
    if (rank == 0) printf("bad inputs:\n");
    ok &= bad_inputs(&v, &ex, rank, size);
    ok &= quaternion_checks(&v, &ex, rank, size);

    free(x), free(want);
    free_view(&v);
    dk_mpi_exchange_free(&ex);
    MPI_Finalize();
    return ok ? 0 : 1;
}

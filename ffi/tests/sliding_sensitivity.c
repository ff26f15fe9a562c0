/* Tangent and adjoint of the deformations with sliding nodes from C99:
 * dk_sensitivity_spring_sliding_tangent, dk_sensitivity_spring_sliding_adjoint_scratch_len,
 * dk_sensitivity_spring_sliding_adjoint, dk_elasticity_sliding_sensitivity_scratch_len,
 * dk_elasticity_sliding_tangent and dk_elasticity_sliding_adjoint (and the _f32 twins) on
 * two meshes turned by 0.3 rad about z, interior jittered:
 *   2D: a 5 x 5 node square of triangles whose edge y = 0 slides on its line;
 *   3D: a 4 x 4 x 4 node cube of hexahedra whose faces z = 0 and y = 0 slide on their planes
 *       and whose common edge slides on its line.
 * Every other boundary node is fixed. Springs on the elasticity graph with Batina's
 * stiffness (CG + Jacobi), elasticity with inverse-volume moduli (one step, block Jacobi).
 *
 * Checks here: the dot-product identity <J v, w> = <v, J^T w> (1e-12 relative in double,
 * 1e-4 in float) for pseudo-random v (at the fixed nodes) and w (everywhere); the spring
 * tangent equals dk_spring_solve_linear_sliding's bits, the elastic tangent plus the points
 * equals dk_elasticity_deform_sliding's bits with one step and v as the displacement; the
 * tangent is v at fixed nodes and in its plane or line at sliding nodes, the adjoint zero off
 * the fixed nodes; bad input (NULL, dim, lengths, NaN, a kind above 3, a direction not unit,
 * a mask that differs from the constraints, a method other than CG, steps other than 1,
 * short scratch) returns its status and leaves the outputs and the report untouched.
 * Prints each case's inputs and the bits of the f64 and f32 results, which
 * host-tests/tests/ffi/c_abi_sliding_sensitivity.rs recomputes with the kernel. Ends with
 * "sliding_sensitivity: every check held" (exit 0), or prints each failed check (exit 1). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

#define MAXN 64            /* nodes of the larger mesh */
#define MAXC 32            /* cells of the larger mesh */
#define MAXV (8 * MAXC)    /* cell nodes */

/* One mesh with its sliding table and fields. */
typedef struct {
    uint32_t dim;
    size_t n, cells, nodes_len, used;
    uint32_t offs[MAXC + 1], offs1[MAXC + 1], nodes[MAXV], nodes1[MAXV];
    uint8_t ckinds[MAXC];
    uint32_t goffs[MAXN + 1], targets[MAXV * 8];
    double pts[3 * MAXN], dirs[3 * MAXN], k[MAXV * 8], v[3 * MAXN], w[3 * MAXN];
    uint8_t kinds[MAXN], mask[MAXN];
} mesh;

static uint64_t seed = 12345;

/* A pseudo-random number in [-1, 1). */
static double rnd(void) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(seed >> 11) / 4503599627370496.0 - 1.0;
}

/* Turns (x, y) by 0.3 rad about z. */
static void turn(double *p) {
    double c = cos(0.3), s = sin(0.3), x = p[0], y = p[1];
    p[0] = c * x - s * y;
    p[1] = s * x + c * y;
}

/* Kind and direction of the node at grid position (i, j[, kk]) of an s-node-wide grid. */
static void table(mesh *m, size_t node, const size_t *ijk, size_t s) {
    size_t d = m->dim, c, hi = 0, low_y = ijk[1] == 0, low_z = d == 3 && ijk[2] == 0;
    double *dir = m->dirs + d * node;
    for (c = 0; c < d; c++) hi |= ijk[c] == s - 1;
    hi |= ijk[0] == 0;
    memset(dir, 0, d * sizeof *dir);
    if (hi || (!low_y && !low_z)) {
        m->kinds[node] = (uint8_t)(hi || low_y || low_z);
    } else if (low_y && low_z) {
        m->kinds[node] = 3; /* the common edge: slides along x */
        dir[0] = 1.0;
        turn(dir);
    } else {
        m->kinds[node] = 2; /* normal e_y on y = 0, e_z on z = 0 */
        dir[low_y ? 1 : 2] = 1.0;
        turn(dir);
    }
    m->mask[node] = m->kinds[node] == 1;
}

/* The 2D square: two triangles per cell. */
static void square(mesh *m) {
    const size_t s = 5;
    size_t i, j, c = 0;
    m->dim = 2;
    m->n = s * s;
    for (j = 0; j < s; j++)
        for (i = 0; i < s; i++) {
            size_t n = i + s * j, ij[2];
            int edge = i == 0 || j == 0 || i == s - 1 || j == s - 1;
            m->pts[2 * n] = ((double)i + (edge ? 0.0 : 0.15 * rnd())) / (double)(s - 1);
            m->pts[2 * n + 1] = ((double)j + (edge ? 0.0 : 0.15 * rnd())) / (double)(s - 1);
            turn(m->pts + 2 * n);
            ij[0] = i;
            ij[1] = j;
            table(m, n, ij, s);
        }
    m->offs[0] = 0;
    for (j = 0; j + 1 < s; j++)
        for (i = 0; i + 1 < s; i++) {
            uint32_t a = (uint32_t)(i + s * j), b = (uint32_t)s;
            uint32_t t[6] = {a, a + 1, a + 1 + b, a, a + 1 + b, a + b};
            memcpy(m->nodes + 3 * c, t, sizeof t);
            m->ckinds[c] = m->ckinds[c + 1] = 5;
            m->offs[c + 1] = (uint32_t)(3 * c + 3);
            m->offs[c + 2] = (uint32_t)(3 * c + 6);
            c += 2;
        }
    m->cells = c;
    m->nodes_len = 3 * c;
}

/* The 3D cube: hexahedra in VTK order. */
static void cube(mesh *m) {
    const size_t s = 4;
    size_t i, j, kk, c = 0, q;
    m->dim = 3;
    m->n = s * s * s;
    for (kk = 0; kk < s; kk++)
        for (j = 0; j < s; j++)
            for (i = 0; i < s; i++) {
                size_t n = i + s * (j + s * kk), ijk[3];
                int edge = i == 0 || j == 0 || kk == 0 || i == s - 1 || j == s - 1 || kk == s - 1;
                for (q = 0; q < 3; q++) {
                    size_t g = q == 0 ? i : q == 1 ? j : kk;
                    m->pts[3 * n + q] = ((double)g + (edge ? 0.0 : 0.15 * rnd())) / (double)(s - 1);
                }
                turn(m->pts + 3 * n);
                ijk[0] = i;
                ijk[1] = j;
                ijk[2] = kk;
                table(m, n, ijk, s);
            }
    m->offs[0] = 0;
    for (kk = 0; kk + 1 < s; kk++)
        for (j = 0; j + 1 < s; j++)
            for (i = 0; i + 1 < s; i++) {
                uint32_t a = (uint32_t)(i + s * (j + s * kk)), r = (uint32_t)s,
                         l = (uint32_t)(s * s);
                uint32_t h[8] = {a, a + 1, a + 1 + r, a + r, a + l, a + 1 + l, a + 1 + r + l, a + r + l};
                memcpy(m->nodes + 8 * c, h, sizeof h);
                m->ckinds[c] = 12;
                m->offs[c + 1] = (uint32_t)(8 * c + 8);
                c++;
            }
    m->cells = c;
    m->nodes_len = 8 * c;
}

/* The graph, the stiffness, 1-based cells and the fields v (fixed nodes) and w. */
static void finish(mesh *m) {
    dk_cells cells = {m->offs, m->cells + 1, m->nodes, m->nodes_len, m->ckinds, m->cells};
    dk_graph graph;
    size_t i, d = m->dim;
    OK(dk_elasticity_graph(m->n, &cells, 0, NULL, 0, m->goffs, m->n + 1, m->targets,
                           sizeof m->targets / sizeof m->targets[0], &m->used));
    graph.offsets = m->goffs;
    graph.offsets_len = m->n + 1;
    graph.targets = m->targets;
    graph.targets_len = m->used;
    OK(dk_spring_batina_stiffness(&graph, m->pts, d * m->n, m->dim, 1.0, m->k, m->used));
    for (i = 0; i <= m->cells; i++) m->offs1[i] = m->offs[i] + 1;
    for (i = 0; i < m->nodes_len; i++) m->nodes1[i] = m->nodes[i] + 1;
    for (i = 0; i < d * m->n; i++) {
        m->v[i] = m->mask[i / d] ? rnd() : 0.0;
        m->w[i] = rnd();
    }
}

static double dot(const double *a, const double *b, size_t len) {
    double s = 0.0;
    size_t k;
    for (k = 0; k < len; k++) s += a[k] * b[k];
    return s;
}

static double dotf(const float *a, const float *b, size_t len) {
    double s = 0.0;
    size_t k;
    for (k = 0; k < len; k++) s += (double)a[k] * (double)b[k];
    return s;
}

/* |<jv, w> - <v, g>| / (|jv| |w|). */
static double identity(double jvw, double vg, double jj, double ww) {
    return fabs(jvw - vg) / sqrt(jj * ww);
}

/* The tangent is v at fixed nodes and lies in each sliding node's plane or on its line; the
 * adjoint is zero off the fixed nodes. */
static void shape(const mesh *m, const double *jv, const double *g) {
    size_t i, c, d = m->dim;
    for (i = 0; i < m->n; i++) {
        const double *x = jv + d * i, *u = m->dirs + d * i;
        double along = 0.0, len = 0.0, off = 0.0;
        for (c = 0; c < d; c++) {
            along += x[c] * u[c];
            len += x[c] * x[c];
        }
        if (m->kinds[i] == 1) {
            for (c = 0; c < d; c++) CHECK(x[c] == m->v[d * i + c]);
            continue;
        }
        for (c = 0; c < d; c++) CHECK(g[d * i + c] == 0.0);
        if (m->kinds[i] == 2) off = fabs(along);
        if (m->kinds[i] == 3)
            for (c = 0; c < d; c++) off = fmax(off, fabs(x[c] - along * u[c]));
        CHECK(off <= 1e-12 * sqrt(len) + 1e-300);
    }
}

/* Prints a mesh's inputs for the host test. */
static void print_inputs(const mesh *m) {
    size_t i, d = m->dim;
    printf("case %u %zu\n", m->dim, m->n);
    printf("cell_offsets");
    for (i = 0; i <= m->cells; i++) printf(" %u", m->offs[i]);
    printf("\ncell_nodes");
    for (i = 0; i < m->nodes_len; i++) printf(" %u", m->nodes[i]);
    printf("\ncell_kinds");
    for (i = 0; i < m->cells; i++) printf(" %u", m->ckinds[i]);
    printf("\n");
    hex64("points", m->pts, d * m->n);
    printf("kinds");
    for (i = 0; i < m->n; i++) printf(" %u", m->kinds[i]);
    printf("\n");
    hex64("dirs", m->dirs, d * m->n);
    hex64("k", m->k, m->used);
    hex64("v", m->v, d * m->n);
    hex64("w", m->w, d * m->n);
}

/* The spring and elastic tangent and adjoint in double: the checks, then the bits. */
static void run64(mesh *m, double *sjv, double *sg, double *ejv, double *eg) {
    size_t d = m->dim, len = d * m->n, tlen, alen, elen, ilen, i;
    dk_graph graph = {m->goffs, m->n + 1, m->targets, m->used};
    dk_spring_system sys = {graph, m->k, m->used, m->mask, m->n};
    dk_constraints con = {m->kinds, m->n, m->dirs, len};
    dk_cells cells = {m->offs, m->cells + 1, m->nodes, m->nodes_len, m->ckinds, m->cells};
    dk_spring_solve_options so;
    dk_elasticity_options eo;
    dk_spring_solve_report r;
    dk_elasticity_report er;
    double *scratch, same[3 * MAXN], moved[3 * MAXN];
    uint32_t iscr[MAXN];
    OK(dk_spring_solve_options_default(&so));
    so.residual_tol = 1e-13;
    so.update_tol = 0.0;
    so.max_iterations = 10000;
    OK(dk_spring_index_scratch_len(m->n, &ilen));
    CHECK(ilen == m->n);
    OK(dk_spring_solve_linear_sliding_scratch_len(m->n, m->dim, &so, &tlen));
    OK(dk_sensitivity_spring_sliding_adjoint_scratch_len(m->n, m->dim, &so, &alen));
    CHECK(alen == d * (6 * m->n + (m->n + d - 1) / d));
    OK(dk_elasticity_sliding_sensitivity_scratch_len(m->n, m->cells, m->used, m->dim, &elen));
    CHECK(elen == m->cells + d * d * (m->n + m->used) + 6 * d * m->n);
    scratch = xmalloc((alen > elen ? alen : elen) * sizeof *scratch);

    /* Springs. */
    memcpy(sjv, m->v, len * sizeof *sjv);
    OK(dk_sensitivity_spring_sliding_tangent(&sys, &con, &so, m->dim, sjv, len, scratch, tlen,
                                             iscr, m->n, &r));
    CHECK(r.converged);
    memcpy(same, m->v, len * sizeof *same);
    OK(dk_spring_solve_linear_sliding(&sys, &con, &so, m->dim, same, len, scratch, tlen, iscr,
                                      m->n, &r));
    SAME(same, sjv, len * sizeof *sjv);
    OK(dk_sensitivity_spring_sliding_adjoint(&sys, &con, &so, m->dim, m->w, len, sg, len,
                                             scratch, alen, iscr, m->n, &r));
    CHECK(r.converged && r.iterations > 0);
    CHECK(identity(dot(sjv, m->w, len), dot(m->v, sg, len), dot(sjv, sjv, len),
                   dot(m->w, m->w, len)) <= 1e-12);
    printf("springs %uD: dot-product identity %.1e\n", m->dim,
           identity(dot(sjv, m->w, len), dot(m->v, sg, len), dot(sjv, sjv, len),
                    dot(m->w, m->w, len)));
    shape(m, sjv, sg);

    /* Elasticity, one step. */
    OK(dk_elasticity_options_default(&eo));
    eo.residual_tol = 1e-13;
    memcpy(ejv, m->v, len * sizeof *ejv);
    OK(dk_elasticity_sliding_tangent(&cells, 0, NULL, 0, &graph, m->dim, m->mask, m->n, &con, &eo,
                                     NULL, 0, m->pts, len, ejv, len, scratch, elen, &r));
    CHECK(r.converged);
    OK(dk_elasticity_sliding_adjoint(&cells, 0, NULL, 0, &graph, m->dim, m->mask, m->n, &con, &eo,
                                     NULL, 0, m->pts, len, m->w, len, eg, len, scratch, elen, &r));
    CHECK(r.converged && r.iterations > 0);
    printf("elasticity %uD: dot-product identity %.1e\n", m->dim,
           identity(dot(ejv, m->w, len), dot(m->v, eg, len), dot(ejv, ejv, len),
                    dot(m->w, m->w, len)));
    CHECK(identity(dot(ejv, m->w, len), dot(m->v, eg, len), dot(ejv, ejv, len),
                   dot(m->w, m->w, len)) <= 1e-12);
    shape(m, ejv, eg);
    /* The forward deformation with v as the displacement moves the points by the tangent. */
    memcpy(moved, m->pts, len * sizeof *moved);
    free(scratch);
    OK(dk_elasticity_sliding_scratch_len(m->n, m->cells, m->used, m->dim, &elen));
    scratch = xmalloc(elen * sizeof *scratch);
    OK(dk_elasticity_deform_sliding(&cells, 0, NULL, 0, &graph, m->dim, m->mask, m->n, &con, &eo,
                                    NULL, 0, m->v, len, moved, len, scratch, elen, &er));
    for (i = 0; i < len; i++) same[i] = m->pts[i] + ejv[i];
    SAME(same, moved, len * sizeof *moved);
    free(scratch);
}

/* The same in float, with 1-based cells for elasticity; the results into the f32 arrays. */
static void run32(const mesh *m, float *sjv, float *sg, float *ejv, float *eg) {
    size_t d = m->dim, len = d * m->n, tlen, alen, elen, i;
    float pts[3 * MAXN], dirs[3 * MAXN], k[MAXV * 8], v[3 * MAXN], w[3 * MAXN], *scratch;
    dk_graph graph = {m->goffs, m->n + 1, m->targets, m->used};
    dk_spring_system_f32 sys = {graph, k, m->used, m->mask, m->n};
    dk_constraints_f32 con = {m->kinds, m->n, dirs, len};
    dk_cells cells1 = {m->offs1, m->cells + 1, m->nodes1, m->nodes_len, m->ckinds, m->cells};
    dk_spring_solve_options so;
    dk_elasticity_options eo;
    dk_spring_solve_report r;
    uint32_t iscr[MAXN + 1 + MAXV];
    for (i = 0; i < len; i++) {
        pts[i] = (float)m->pts[i];
        dirs[i] = (float)m->dirs[i];
        v[i] = (float)m->v[i];
        w[i] = (float)m->w[i];
    }
    for (i = 0; i < m->used; i++) k[i] = (float)m->k[i];
    OK(dk_spring_solve_options_default_f32(&so));
    so.residual_tol = 1e-6;
    so.update_tol = 0.0;
    OK(dk_elasticity_options_default_f32(&eo));
    eo.residual_tol = 1e-6;
    OK(dk_spring_solve_linear_sliding_scratch_len(m->n, m->dim, &so, &tlen));
    OK(dk_sensitivity_spring_sliding_adjoint_scratch_len(m->n, m->dim, &so, &alen));
    OK(dk_elasticity_sliding_sensitivity_scratch_len(m->n, m->cells, m->used, m->dim, &elen));
    scratch = xmalloc((alen > elen ? alen : elen) * sizeof *scratch);
    memcpy(sjv, v, len * sizeof *sjv);
    OK(dk_sensitivity_spring_sliding_tangent_f32(&sys, &con, &so, m->dim, sjv, len, scratch,
                                                 tlen, iscr, m->n, &r));
    OK(dk_sensitivity_spring_sliding_adjoint_f32(&sys, &con, &so, m->dim, w, len, sg, len,
                                                 scratch, alen, iscr, m->n, &r));
    CHECK(identity(dotf(sjv, w, len), dotf(v, sg, len), dotf(sjv, sjv, len),
                   dotf(w, w, len)) <= 1e-4);
    memcpy(ejv, v, len * sizeof *ejv);
    OK(dk_elasticity_sliding_tangent_f32(&cells1, 1, iscr, sizeof iscr / sizeof iscr[0], &graph,
                                         m->dim, m->mask, m->n, &con, &eo, NULL, 0, pts, len,
                                         ejv, len, scratch, elen, &r));
    OK(dk_elasticity_sliding_adjoint_f32(&cells1, 1, iscr, sizeof iscr / sizeof iscr[0], &graph,
                                         m->dim, m->mask, m->n, &con, &eo, NULL, 0, pts, len, w,
                                         len, eg, len, scratch, elen, &r));
    CHECK(identity(dotf(ejv, w, len), dotf(v, eg, len), dotf(ejv, ejv, len),
                   dotf(w, w, len)) <= 1e-4);
    free(scratch);
}


/* Bad input on the 2D mesh: each call returns its status and leaves dx, g and the report
 * untouched (bit for bit). */
static void bad_input(const mesh *m) {
    size_t d = m->dim, len = d * m->n, alen, elen, tlen, keep_len = 77;
    dk_graph graph = {m->goffs, m->n + 1, m->targets, m->used};
    dk_spring_system sys = {graph, m->k, m->used, m->mask, m->n};
    dk_constraints con = {m->kinds, m->n, m->dirs, len}, bad;
    dk_cells cells = {m->offs, m->cells + 1, m->nodes, m->nodes_len, m->ckinds, m->cells};
    dk_spring_solve_options so, gs;
    dk_elasticity_options eo, two;
    dk_spring_solve_report r, r0;
    double dx[3 * MAXN], dx0[3 * MAXN], g[3 * MAXN], g0[3 * MAXN], w[3 * MAXN],
        dirs[3 * MAXN], *scratch;
    uint8_t kinds[MAXN], mask[MAXN];
    uint32_t iscr[MAXN];
    float dx32[3 * MAXN], dx32_0[3 * MAXN];
    dk_spring_system_f32 sys32 = {graph, NULL, 0, m->mask, m->n};
    dk_constraints_f32 con32 = {m->kinds, m->n, NULL, 0};
    OK(dk_spring_solve_options_default(&so));
    OK(dk_elasticity_options_default(&eo));
    OK(dk_spring_solve_linear_sliding_scratch_len(m->n, m->dim, &so, &tlen));
    OK(dk_sensitivity_spring_sliding_adjoint_scratch_len(m->n, m->dim, &so, &alen));
    OK(dk_elasticity_sliding_sensitivity_scratch_len(m->n, m->cells, m->used, m->dim, &elen));
    scratch = xmalloc((alen > elen ? alen : elen) * sizeof *scratch);
    memcpy(dx, m->v, len * sizeof *dx);
    memcpy(dx0, dx, sizeof dx);
    memset(g, 0x5a, sizeof g);
    memcpy(g0, g, sizeof g);
    memcpy(w, m->w, len * sizeof *w);
    POISON(r);
    memcpy(&r0, &r, sizeof r);
    gs = so;
    gs.method = DK_LINEAR_GAUSS_SEIDEL;
    two = eo;
    two.steps = 2;

    /* The scratch queries. */
    EXPECT(dk_sensitivity_spring_sliding_adjoint_scratch_len(m->n, m->dim, &gs, &keep_len),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_sensitivity_spring_sliding_adjoint_scratch_len(m->n, 4, &so, &keep_len),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_sensitivity_spring_sliding_adjoint_scratch_len(m->n, m->dim, NULL, &keep_len),
           DK_ERR_NULL_POINTER);
    EXPECT(dk_sensitivity_spring_sliding_adjoint_scratch_len(SIZE_MAX / 2, m->dim, &so,
                                                             &keep_len),
           DK_ERR_TOO_LARGE);
    EXPECT(dk_elasticity_sliding_sensitivity_scratch_len(m->n, m->cells, m->used, 1, &keep_len),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_sliding_sensitivity_scratch_len(SIZE_MAX / 2, m->cells, m->used, 2,
                                                         &keep_len),
           DK_ERR_TOO_LARGE);
    CHECK(keep_len == 77);

    /* The spring tangent. */
    EXPECT(dk_sensitivity_spring_sliding_tangent(NULL, &con, &so, 2, dx, len, scratch, tlen,
                                                 iscr, m->n, &r),
           DK_ERR_NULL_POINTER);
    EXPECT(dk_sensitivity_spring_sliding_tangent(&sys, &con, &so, 4, dx, len, scratch, tlen,
                                                 iscr, m->n, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_sensitivity_spring_sliding_tangent(&sys, &con, &so, 2, dx, len - 1, scratch, tlen,
                                                 iscr, m->n, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_sensitivity_spring_sliding_tangent(&sys, &con, &so, 2, dx, len, scratch, tlen - 1,
                                                 iscr, m->n, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(dk_sensitivity_spring_sliding_tangent(&sys, &con, &so, 2, dx, len, scratch, tlen,
                                                 iscr, m->n, NULL),
           DK_ERR_NULL_POINTER);
    memset(dx32, 0, sizeof dx32);
    memcpy(dx32_0, dx32, sizeof dx32);
    EXPECT(dk_sensitivity_spring_sliding_tangent_f32(&sys32, &con32, &so, 2, dx32, len, NULL, 0,
                                                     iscr, m->n, &r),
           DK_ERR_LENGTH_MISMATCH); /* no directions for the nodes */
    SAME(dx32, dx32_0, sizeof dx32);

    /* The spring adjoint. */
    EXPECT(dk_sensitivity_spring_sliding_adjoint(&sys, &con, &gs, 2, w, len, g, len, scratch,
                                                 alen, iscr, m->n, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_sensitivity_spring_sliding_adjoint(&sys, &con, &so, 2, w, len, g, len, scratch,
                                                 alen - 1, iscr, m->n, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(dk_sensitivity_spring_sliding_adjoint(&sys, &con, &so, 2, w, len, g, len - 2,
                                                 scratch, alen, iscr, m->n, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_sensitivity_spring_sliding_adjoint(&sys, &con, &so, 2, w, len, NULL, len, scratch,
                                                 alen, iscr, m->n, &r),
           DK_ERR_NULL_POINTER);
    w[3] = NAN;
    EXPECT(dk_sensitivity_spring_sliding_adjoint(&sys, &con, &so, 2, w, len, g, len, scratch,
                                                 alen, iscr, m->n, &r),
           DK_ERR_NON_FINITE);
    w[3] = m->w[3];
    memcpy(kinds, m->kinds, m->n);
    memcpy(dirs, m->dirs, len * sizeof *dirs);
    bad = con;
    bad.kinds = kinds;
    bad.directions = dirs;
    kinds[7] = 4;
    EXPECT(dk_sensitivity_spring_sliding_adjoint(&sys, &bad, &so, 2, w, len, g, len, scratch,
                                                 alen, iscr, m->n, &r),
           DK_ERR_INDEX_OUT_OF_RANGE);
    kinds[7] = m->kinds[7];
    dirs[2] *= 1.001; /* node 1 slides: its normal no longer unit */
    CHECK(m->kinds[1] == 2);
    EXPECT(dk_sensitivity_spring_sliding_adjoint(&sys, &bad, &so, 2, w, len, g, len, scratch,
                                                 alen, iscr, m->n, &r),
           DK_ERR_NOT_UNIT);
    dirs[2] = NAN;
    EXPECT(dk_sensitivity_spring_sliding_adjoint(&sys, &bad, &so, 2, w, len, g, len, scratch,
                                                 alen, iscr, m->n, &r),
           DK_ERR_NON_FINITE);
    dirs[2] = m->dirs[2];
    bad.kinds_len = m->n - 1;
    bad.directions_len = len - 2;
    EXPECT(dk_sensitivity_spring_sliding_adjoint(&sys, &bad, &so, 2, w, len, g, len, scratch,
                                                 alen, iscr, m->n, &r),
           DK_ERR_LENGTH_MISMATCH);
    memcpy(mask, m->mask, m->n);
    mask[1] = 1; /* fixed in the system, sliding in the constraints */
    sys.fixed = mask;
    EXPECT(dk_sensitivity_spring_sliding_adjoint(&sys, &con, &so, 2, w, len, g, len, scratch,
                                                 alen, iscr, m->n, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_sensitivity_spring_sliding_tangent(&sys, &con, &so, 2, dx, len, scratch, tlen,
                                                 iscr, m->n, &r),
           DK_ERR_INVALID_PARAMETER);
    sys.fixed = m->mask;

    /* The elastic tangent and adjoint. */
    EXPECT(dk_elasticity_sliding_tangent(&cells, 0, NULL, 0, &graph, 2, m->mask, m->n, &con,
                                         &two, NULL, 0, m->pts, len, dx, len, scratch, elen, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_sliding_tangent(&cells, 0, NULL, 0, &graph, 2, m->mask, m->n, &con,
                                         &eo, NULL, 0, m->pts, len, dx, len, scratch, elen - 1,
                                         &r),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(dk_elasticity_sliding_tangent(&cells, 0, NULL, 0, &graph, 3, m->mask, m->n, &con,
                                         &eo, NULL, 0, m->pts, len, dx, len, scratch, elen, &r),
           DK_ERR_LENGTH_MISMATCH); /* 50 scalars are not 3D points */
    EXPECT(dk_elasticity_sliding_tangent(&cells, 0, NULL, 0, &graph, 2, m->mask, m->n, NULL,
                                         &eo, NULL, 0, m->pts, len, dx, len, scratch, elen, &r),
           DK_ERR_NULL_POINTER);
    EXPECT(dk_elasticity_sliding_tangent(&cells, 0, NULL, 0, &graph, 2, mask, m->n, &con, &eo,
                                         NULL, 0, m->pts, len, dx, len, scratch, elen, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_elasticity_sliding_tangent(&cells, 2, iscr, m->n, &graph, 2, m->mask, m->n, &con,
                                         &eo, NULL, 0, m->pts, len, dx, len, scratch, elen, &r),
           DK_ERR_BAD_INDEX_BASE);
    dx[0] = NAN;
    memcpy(dx0, dx, sizeof dx);
    EXPECT(dk_elasticity_sliding_tangent(&cells, 0, NULL, 0, &graph, 2, m->mask, m->n, &con,
                                         &eo, NULL, 0, m->pts, len, dx, len, scratch, elen, &r),
           DK_ERR_NON_FINITE);
    EXPECT(dk_sensitivity_spring_sliding_tangent(&sys, &con, &so, 2, dx, len, scratch, tlen,
                                                 iscr, m->n, &r),
           DK_ERR_NON_FINITE);
    EXPECT(dk_elasticity_sliding_adjoint(&cells, 0, NULL, 0, &graph, 2, m->mask, m->n, &bad,
                                         &eo, NULL, 0, m->pts, len, w, len, g, len, scratch,
                                         elen, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_elasticity_sliding_adjoint(&cells, 0, NULL, 0, &graph, 2, m->mask, m->n, &con,
                                         &two, NULL, 0, m->pts, len, w, len, g, len, scratch,
                                         elen, &r),
           DK_ERR_INVALID_PARAMETER);
    w[5] = INFINITY;
    EXPECT(dk_elasticity_sliding_adjoint(&cells, 0, NULL, 0, &graph, 2, m->mask, m->n, &con,
                                         &eo, NULL, 0, m->pts, len, w, len, g, len, scratch,
                                         elen, &r),
           DK_ERR_NON_FINITE);
    w[5] = m->w[5];
    EXPECT(dk_elasticity_sliding_adjoint(&cells, 0, NULL, 0, &graph, 2, m->mask, m->n, &con,
                                         &eo, NULL, 0, m->pts, len, w, len - 2, g, len - 2,
                                         scratch, elen, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_elasticity_sliding_adjoint(&cells, 0, NULL, 0, NULL, 2, m->mask, m->n, &con, &eo,
                                         NULL, 0, m->pts, len, w, len, g, len, scratch, elen,
                                         &r),
           DK_ERR_NULL_POINTER);
    SAME(dx, dx0, sizeof dx);
    SAME(g, g0, sizeof g);
    SAME(&r, &r0, sizeof r);
    free(scratch);
}

static mesh meshes[2];

int main(void) {
    double sjv[3 * MAXN], sg[3 * MAXN], ejv[3 * MAXN], eg[3 * MAXN];
    float sjv32[3 * MAXN], sg32[3 * MAXN], ejv32[3 * MAXN], eg32[3 * MAXN];
    size_t c;
    square(&meshes[0]);
    cube(&meshes[1]);
    for (c = 0; c < 2; c++) {
        mesh *m = &meshes[c];
        size_t len = m->dim * m->n;
        finish(m);
        print_inputs(m);
        run64(m, sjv, sg, ejv, eg);
        hex64("spring_jv", sjv, len);
        hex64("spring_g", sg, len);
        hex64("elastic_jv", ejv, len);
        hex64("elastic_g", eg, len);
        run32(m, sjv32, sg32, ejv32, eg32);
        hex32("spring_jv32", sjv32, len);
        hex32("spring_g32", sg32, len);
        hex32("elastic_jv32", ejv32, len);
        hex32("elastic_g32", eg32, len);
    }
    bad_input(&meshes[0]);
    if (failures) return 1;
    printf("sliding_sensitivity: every check held\n");
    return 0;
}

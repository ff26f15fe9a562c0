/* The quaternion deformation C ABI (dk_deform_*, dk_boundary_motion_*): every function, f64 and
 * _f32, with results checked independently of the library (a rigid rotation + translation of
 * every boundary must move every interior node rigidly; boundary nodes are bitwise the
 * prescribed positions; uniform fields are reproduced; renumbering by hand), and bad input:
 * each call returns its documented status and leaves its outputs untouched.
 *
 * The precision-generic part is compiled twice by including this file into itself, once with
 * REAL = double and once with REAL = float (names get the _f32 suffix). Exits non-zero, printing
 * the failed checks, on any deviation. */
#ifndef REAL

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "deform_kernel.h"

static int failures = 0;

#define EXPECT(call, status)                                                              \
    do {                                                                                  \
        dk_status s_ = (call);                                                            \
        if (s_ != (status)) {                                                             \
            printf("FAIL line %d %s: got %d (%s), expected %d\n", __LINE__, #call, (int)s_, \
                   dk_status_str((int32_t)s_), (int)(status));                            \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

#define OK(call) EXPECT(call, DK_OK)

#define TRUE_(cond, what)                                                                 \
    do {                                                                                  \
        if (!(cond)) {                                                                    \
            printf("FAIL line %d: %s\n", __LINE__, what);                                 \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

/* Every entry of buf[0..n) still holds the sentinel. */
#define UNTOUCHED(buf, n)                                                                 \
    do {                                                                                  \
        size_t i_;                                                                        \
        for (i_ = 0; i_ < (size_t)(n); i_++)                                              \
            if ((buf)[i_] != SENTINEL) {                                                  \
                printf("FAIL line %d: %s[%zu] was written\n", __LINE__, #buf, i_);        \
                failures++;                                                               \
                break;                                                                    \
            }                                                                             \
    } while (0)

#define SENTINEL 12345
#define FILL(buf, n)                                                                      \
    do {                                                                                  \
        size_t i_;                                                                        \
        for (i_ = 0; i_ < (size_t)(n); i_++) (buf)[i_] = SENTINEL;                        \
    } while (0)

/* The 2D test grid: NX x NY points on [0, 1] x [0, 0.8], i fastest; the boundary is the
 * perimeter, listed counter-clockwise from (0, 0). */
#define NX 7
#define NY 6
#define N2 (NX * NY)
#define B2 (2 * (NX + NY) - 4)
/* The 3D test block: MX x MY x MZ points, every point on a face is a boundary node. */
#define MX 4
#define MY 4
#define MZ 3
#define N3 (MX * MY * MZ)
#define NC2 ((NX - 1) * (NY - 1))
#define WORK 4096

static uint32_t perimeter[B2];           /* mesh node of each boundary point */
static uint32_t seg_offsets[B2 + 1];     /* the closed loop as segments, 0-based */
static uint32_t seg_nodes[2 * B2];
static uint8_t seg_kinds[B2];
static uint32_t graph_offsets[N2 + 1];   /* edge graph of the 2D grid's quads */
static uint32_t graph_targets[8 * NC2];
static size_t graph_len;
static dk_graph grid_graph;              /* the two above, as the ABI takes them */
static uint8_t fixed2[N2];
static uint32_t boundary3[N3];
static size_t nb3;

static void setup(void) {
    size_t k = 0, i, j, c;
    uint32_t co[NC2 + 1], cn[4 * NC2];
    uint8_t ck[NC2];
    const dk_cells quads = {co, NC2 + 1, cn, 4 * NC2, ck, NC2};
    size_t len = 0;
    for (i = 0; i < NX; i++) perimeter[k++] = (uint32_t)i;
    for (j = 1; j < NY; j++) perimeter[k++] = (uint32_t)(NX - 1 + NX * j);
    for (i = NX - 1; i-- > 0;) perimeter[k++] = (uint32_t)(i + NX * (NY - 1));
    for (j = NY - 1; j-- > 1;) perimeter[k++] = (uint32_t)(NX * j);
    for (k = 0; k < B2; k++) {
        seg_offsets[k] = (uint32_t)(2 * k);
        seg_nodes[2 * k] = (uint32_t)k;
        seg_nodes[2 * k + 1] = (uint32_t)((k + 1) % B2);
        seg_kinds[k] = 3;
    }
    seg_offsets[B2] = 2 * B2;
    for (c = 0; c < NC2; c++) {
        size_t ci = c % (NX - 1), cj = c / (NX - 1);
        co[c] = (uint32_t)(4 * c);
        cn[4 * c] = (uint32_t)(ci + NX * cj);
        cn[4 * c + 1] = (uint32_t)(ci + 1 + NX * cj);
        cn[4 * c + 2] = (uint32_t)(ci + 1 + NX * (cj + 1));
        cn[4 * c + 3] = (uint32_t)(ci + NX * (cj + 1));
        ck[c] = 9;
    }
    co[NC2] = 4 * NC2;
    OK(dk_graph_from_cells_len(N2, &quads, 0, NULL, 0, false, &len));
    OK(dk_graph_from_cells(N2, &quads, 0, NULL, 0, false, graph_offsets, N2 + 1, graph_targets,
                           len, &graph_len));
    grid_graph = (dk_graph){graph_offsets, N2 + 1, graph_targets, graph_len};
    memset(fixed2, 0, sizeof fixed2);
    for (k = 0; k < B2; k++) fixed2[perimeter[k]] = 1;
    nb3 = 0;
    for (c = 0; c < N3; c++) {
        size_t x = c % MX, y = c / MX % MY, z = c / (MX * MY);
        if (x == 0 || x == MX - 1 || y == 0 || y == MY - 1 || z == 0 || z == MZ - 1)
            boundary3[nb3++] = (uint32_t)c;
    }
}

/* Rigid motions used throughout: 2D rotation by A2 about P2 then translation T2; 3D rotation
 * by A3 about the unit axis AX3 through P3, then translation T3. */
static const double A2 = 0.4, P2[2] = {0.3, 0.2}, T2[2] = {0.15, -0.05};
static const double A3 = 0.7, P3[3] = {0.5, 0.5, 0.25}, T3[3] = {0.1, 0.2, -0.3};
static double AX3[3];

static void rigid2(const double *p, double *out) {
    double c = cos(A2), s = sin(A2), x = p[0] - P2[0], y = p[1] - P2[1];
    out[0] = c * x - s * y + P2[0] + T2[0];
    out[1] = s * x + c * y + P2[1] + T2[1];
}

static void rigid3(const double *p, double *out) {
    double c = cos(A3), s = sin(A3), v[3], d, cr[3];
    int k;
    for (k = 0; k < 3; k++) v[k] = p[k] - P3[k];
    d = AX3[0] * v[0] + AX3[1] * v[1] + AX3[2] * v[2];
    cr[0] = AX3[1] * v[2] - AX3[2] * v[1];
    cr[1] = AX3[2] * v[0] - AX3[0] * v[2];
    cr[2] = AX3[0] * v[1] - AX3[1] * v[0];
    for (k = 0; k < 3; k++) out[k] = v[k] * c + cr[k] * s + AX3[k] * d * (1 - c) + P3[k] + T3[k];
}

static void type_independent(void) {
    size_t len = 7, len2 = 7;
    dk_spring_solve_options o;
    uint32_t boundary[3] = {5, 2, 9}, global[4] = {9, 5, 2, 2}, local[4], scratch[32];
    uint32_t boundary1[3] = {6, 3, 10}, global1[4] = {10, 6, 3, 3}, dup[3] = {5, 2, 5};
    uint32_t missing[1] = {4};

    OK(dk_deform_idw_scratch_len(100, 10, 2, &len));
    TRUE_(len == 100, "idw scratch len 2D = max(N, 3B)");
    OK(dk_deform_idw_scratch_len(10, 10, 3, &len));
    TRUE_(len == 130, "idw scratch len 3D = max(N, 13B)");
    OK(dk_deform_tfi_scratch_len(4, 5, 1, 3, 2, &len));
    TRUE_(len == 40, "tfi scratch len = max(dim N, rotation scratch)");
    OK(dk_deform_propagate_tfi_scratch_len(4, 5, 6, 3, &len));
    TRUE_(len == 360, "propagate tfi scratch len = dim N");
    OK(dk_deform_boundary_normals_scratch_len(11, &len));
    TRUE_(len == 33, "normals scratch len = 3B");
    OK(dk_deform_boundary_rotations_scratch_len(11, 2, &len));
    TRUE_(len == 33, "rotations scratch len 2D = 3B");
    OK(dk_deform_boundary_rotations_scratch_len(11, 3, &len));
    TRUE_(len == 143, "rotations scratch len 3D = 13B");
    OK(dk_deform_localize_nodes_scratch_len(20, 3, 4, 0, &len));
    TRUE_(len == 20, "localize scratch len, base 0");
    OK(dk_deform_localize_nodes_scratch_len(20, 3, 4, 1, &len));
    TRUE_(len == 27, "localize scratch len, base 1");
    OK(dk_spring_solve_options_default(&o));
    o.method = DK_LINEAR_GAUSS_SEIDEL;
    OK(dk_deform_spring_scratch_len(50, 10, 2, &o, &len, &len2));
    TRUE_(len == 50 && len2 == 300, "spring scratch lens (Gauss-Seidel: N items of dim + 4)");
    OK(dk_deform_propagate_spring_scratch_len(50, 3, &o, &len));
    TRUE_(len == 350, "propagate spring values len");

    /* Bad input to the queries: nothing written. */
    len = 7;
    len2 = 7;
    EXPECT(dk_deform_idw_scratch_len(10, 10, 4, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_deform_idw_scratch_len(10, 10, 2, NULL), DK_ERR_NULL_POINTER);
    EXPECT(dk_deform_tfi_scratch_len(0, 5, 1, 3, 2, &len), DK_ERR_BAD_DIMENSIONS);
    EXPECT(dk_deform_propagate_tfi_scratch_len(4, 5, 1, 1, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_deform_boundary_rotations_scratch_len(3, 0, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_deform_localize_nodes_scratch_len(20, 3, 4, 2, &len), DK_ERR_BAD_INDEX_BASE);
    EXPECT(dk_deform_localize_nodes_scratch_len(20, (size_t)-1, 4, 1, &len), DK_ERR_TOO_LARGE);
    EXPECT(dk_deform_spring_scratch_len(50, 10, 2, &o, &len, &len), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_deform_spring_scratch_len(50, 10, 2, NULL, &len, &len2), DK_ERR_NULL_POINTER);
    o.method = 42;
    EXPECT(dk_deform_spring_scratch_len(50, 10, 2, &o, &len, &len2), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_deform_propagate_spring_scratch_len(50, 3, &o, &len), DK_ERR_INVALID_PARAMETER);
    TRUE_(len == 7 && len2 == 7, "a failed query wrote its output");

    /* Renumbering, 0- and 1-based. */
    OK(dk_deform_localize_nodes(12, boundary, 3, global, 4, 0, scratch, 32, local, 4));
    TRUE_(local[0] == 2 && local[1] == 0 && local[2] == 1 && local[3] == 1, "localize 0-based");
    OK(dk_deform_localize_nodes(12, boundary1, 3, global1, 4, 1, scratch, 32, local, 4));
    TRUE_(local[0] == 3 && local[1] == 1 && local[2] == 2 && local[3] == 2, "localize 1-based");
    FILL(local, 4);
    EXPECT(dk_deform_localize_nodes(12, dup, 3, global, 4, 0, scratch, 32, local, 4),
           DK_ERR_DUPLICATE_NODE);
    EXPECT(dk_deform_localize_nodes(12, boundary, 3, missing, 1, 0, scratch, 32, local, 1),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(dk_deform_localize_nodes(9, boundary, 3, global, 4, 0, scratch, 32, local, 4),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(dk_deform_localize_nodes(12, boundary, 3, global, 4, 2, scratch, 32, local, 4),
           DK_ERR_BAD_INDEX_BASE);
    EXPECT(dk_deform_localize_nodes(12, boundary1, 3, global1, 4, 1, scratch, 18, local, 4),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(dk_deform_localize_nodes(12, boundary, 3, global, 4, 0, scratch, 32, local, 3),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_deform_localize_nodes(12, NULL, 3, global, 4, 0, scratch, 32, local, 4),
           DK_ERR_NULL_POINTER);
    EXPECT(dk_deform_localize_nodes(12, boundary, 3, global, 4, 0, scratch, 32, NULL, 4),
           DK_ERR_NULL_POINTER);
    UNTOUCHED(local, 4);
}

/* The precision-generic tests, once per precision. */
#define REAL double
#define SFX(name) name
#define TOL 1e-12
#define SUFFIX_STR ""
#include "deformation.c" /* this file, second pass */
#undef REAL
#undef SFX
#undef TOL
#undef SUFFIX_STR
#define REAL float
#define SFX(name) name##_f32
#define TOL 2e-5
#define SUFFIX_STR "_f32"
#include "deformation.c" /* this file, second pass */

int main(void) {
    double n = sqrt(3.0);
    AX3[0] = 1.0 / n;
    AX3[1] = 1.0 / n;
    AX3[2] = 1.0 / n;
    setup();
    type_independent();
    generic_tests();
    generic_tests_f32();
    if (failures == 0)
        printf("deformation: every check held\n");
    else
        printf("deformation: %d checks failed\n", failures);
    return failures == 0 ? 0 : 1;
}

#else /* ------------------------------------------------------------------------------------ */
/* The generic part: REAL, SFX(), TOL and SUFFIX_STR are defined by the includer. */

#define NEAR(a, b, what)                                                                  \
    do {                                                                                  \
        double a_ = (double)(a), b_ = (double)(b);                                        \
        if (!(fabs(a_ - b_) <= TOL * (1.0 + fabs(b_)))) {                                 \
            printf("FAIL line %d%s: %s: %.17g vs %.17g\n", __LINE__, SUFFIX_STR, what, a_, \
                   b_);                                                                   \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

/* Quaternion of the 2D rigid rotation and of the 3D one. */
static void SFX(q2)(REAL *q) {
    q[0] = (REAL)cos(A2 / 2);
    q[1] = 0;
    q[2] = 0;
    q[3] = (REAL)sin(A2 / 2);
}

static void SFX(q3)(REAL *q) {
    int k;
    q[0] = (REAL)cos(A3 / 2);
    for (k = 0; k < 3; k++) q[k + 1] = (REAL)(sin(A3 / 2) * AX3[k]);
}

static void SFX(grid2)(REAL *p) {
    size_t i;
    for (i = 0; i < N2; i++) {
        p[2 * i] = (REAL)((double)(i % NX) / (NX - 1));
        p[2 * i + 1] = (REAL)(0.8 * (double)(i / NX) / (NY - 1));
    }
}

static void SFX(grid3)(REAL *p) {
    size_t i;
    for (i = 0; i < N3; i++) {
        p[3 * i] = (REAL)((double)(i % MX) / (MX - 1));
        p[3 * i + 1] = (REAL)((double)(i / MX % MY) / (MY - 1));
        p[3 * i + 2] = (REAL)(0.5 * (double)(i / (MX * MY)) / (MZ - 1));
    }
}

/* out holds the image of every point of p (n points of dim) under the rigid motion, and every
 * boundary node is bitwise its prescribed position. */
static void SFX(check_rigid)(const REAL *p, const REAL *out, size_t n, int dim,
                             const uint32_t *bnodes, const REAL *bdef, size_t nb,
                             const char *what) {
    size_t i;
    int k;
    for (i = 0; i < n; i++) {
        double x[3], y[3];
        for (k = 0; k < dim; k++) x[k] = (double)p[dim * i + k];
        if (dim == 2)
            rigid2(x, y);
        else
            rigid3(x, y);
        for (k = 0; k < dim; k++) NEAR(out[dim * i + k], y[k], what);
    }
    for (i = 0; i < nb; i++)
        for (k = 0; k < dim; k++)
            if (memcmp(&out[dim * bnodes[i] + k], &bdef[dim * i + k], sizeof(REAL)) != 0) {
                printf("FAIL%s %s: boundary point %zu is not bitwise its prescribed position\n",
                       SUFFIX_STR, what, i);
                failures++;
                return;
            }
}

/* Tangent and adjoint of the IDW deformation of the rigid motion m (dk_deform_idw_tangent,
 * dk_deform_idw_adjoint): the deformation of a rigid motion is rigid, so the tangent along a
 * further unit rotation about P2 is the rigid field (-(y - P2y), x - P2x) at the deformed
 * points out; the adjoint is its transpose (dot-product test). */
static void SFX(idw_sensitivities)(const REAL *p, const REAL *out,
                                   const SFX(dk_boundary_motion) * m) {
    static REAL scratch[WORK], dir[2 * B2], tan[2 * N2], w[2 * N2], back[2 * B2];
    size_t i, len;
    double jv_w = 0, v_jtw = 0, scale = 0;
    OK(dk_deform_idw_sensitivity_scratch_len(N2, B2, 2, &len));
    TRUE_(len == 32 * B2, "sensitivity scratch len = max(N, 32 B)");
    for (i = 0; i < B2; i++) {
        dir[2 * i] = -(m->deformed[2 * i + 1] - (REAL)P2[1]);
        dir[2 * i + 1] = m->deformed[2 * i] - (REAL)P2[0];
    }
    OK(SFX(dk_deform_idw_tangent)(p, 2 * N2, 2, m, 3, dir, 2 * B2, scratch, len, NULL, 0, tan,
                                  2 * N2));
    for (i = 0; i < N2; i++) {
        NEAR(tan[2 * i], -((double)out[2 * i + 1] - P2[1]), "idw tangent of a rigid rotation");
        NEAR(tan[2 * i + 1], (double)out[2 * i] - P2[0], "idw tangent of a rigid rotation");
    }
    for (i = 0; i < 2 * N2; i++) w[i] = (REAL)sin(1.0 + 0.7 * (double)i);
    OK(SFX(dk_deform_idw_adjoint)(p, 2 * N2, 2, m, 3, w, 2 * N2, scratch, len, NULL, 0, back,
                                  2 * B2));
    for (i = 0; i < 2 * N2; i++) {
        jv_w += (double)tan[i] * (double)w[i];
        scale += fabs((double)tan[i] * (double)w[i]);
    }
    for (i = 0; i < 2 * B2; i++) v_jtw += (double)dir[i] * (double)back[i];
    NEAR(jv_w / scale, v_jtw / scale, "idw adjoint: <J v, w> = <v, J^T w>");
    /* Bad input: nothing written. */
    FILL(back, 2 * B2);
    EXPECT(SFX(dk_deform_idw_adjoint)(p, 2 * N2, 2, m, 3, w, 2 * N2 - 1, scratch, len, NULL, 0,
                                      back, 2 * B2),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_idw_adjoint)(p, 2 * N2, 2, m, 3, w, 2 * N2, scratch, B2, NULL, 0, back,
                                      2 * B2),
           DK_ERR_BUFFER_TOO_SMALL);
    UNTOUCHED(back, 2 * B2);
    FILL(tan, 2 * N2);
    EXPECT(SFX(dk_deform_idw_tangent)(p, 2 * N2, 4, m, 3, dir, 2 * B2, scratch, len, NULL, 0,
                                      tan, 2 * N2),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_deform_idw_tangent)(p, 2 * N2, 2, m, -1, dir, 2 * B2, scratch, len, NULL, 0,
                                      tan, 2 * N2),
           DK_ERR_INVALID_PARAMETER);
    UNTOUCHED(tan, 2 * N2);
}

/* Tangent and adjoint of the TFI deformation of the motion m (dk_deform_tfi_tangent,
 * dk_deform_tfi_adjoint): the dot-product test <J v, w> = <v, J^T w> for smooth v, w, the
 * scratch length, and bad input that writes nothing. */
static void SFX(tfi_sensitivities)(const REAL *p, const SFX(dk_boundary_motion) * m) {
    static REAL scratch[WORK], dir[2 * B2], tan[2 * N2], w[2 * N2], back[2 * B2];
    static uint32_t idx[WORK];
    const uint32_t ij = DK_DIRECTION_I | DK_DIRECTION_J;
    size_t i, len;
    double jv_w = 0, v_jtw = 0, scale = 0;
    OK(dk_deform_tfi_sensitivity_scratch_len(NX, NY, 1, B2, 2, &len));
    TRUE_(len == 32 * B2 + 13 * N2, "tfi sensitivity scratch len = max(N, 32 B) + 13 N");
    for (i = 0; i < 2 * B2; i++) dir[i] = (REAL)sin(0.3 + 1.1 * (double)i);
    for (i = 0; i < 2 * N2; i++) w[i] = (REAL)cos(0.2 + 0.9 * (double)i);
    OK(SFX(dk_deform_tfi_tangent)(NX, NY, 1, ij, p, 2 * N2, 2, m, dir, 2 * B2, scratch, len,
                                  idx, WORK, tan, 2 * N2));
    OK(SFX(dk_deform_tfi_adjoint)(NX, NY, 1, ij, p, 2 * N2, 2, m, w, 2 * N2, scratch, len, idx,
                                  WORK, back, 2 * B2));
    for (i = 0; i < 2 * N2; i++) {
        jv_w += (double)tan[i] * (double)w[i];
        scale += fabs((double)tan[i] * (double)w[i]);
    }
    for (i = 0; i < 2 * B2; i++) v_jtw += (double)dir[i] * (double)back[i];
    TRUE_(scale > 1, "tfi tangent is not zero");
    NEAR(jv_w / scale, v_jtw / scale, "tfi adjoint: <J v, w> = <v, J^T w>");
    /* Bad input: nothing written. */
    FILL(back, 2 * B2);
    EXPECT(SFX(dk_deform_tfi_adjoint)(NX, NY, 1, ij, p, 2 * N2, 2, m, w, 2 * N2 - 1, scratch,
                                      len, idx, WORK, back, 2 * B2),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_tfi_adjoint)(NX, NY, 1, ij, p, 2 * N2, 2, m, w, 2 * N2, scratch,
                                      len - 1, idx, WORK, back, 2 * B2),
           DK_ERR_BUFFER_TOO_SMALL);
    UNTOUCHED(back, 2 * B2);
    FILL(tan, 2 * N2);
    EXPECT(SFX(dk_deform_tfi_tangent)(NX, NY, 1, 8, p, 2 * N2, 2, m, dir, 2 * B2, scratch, len,
                                      idx, WORK, tan, 2 * N2),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_deform_tfi_tangent)(NX, 0, 1, ij, p, 2 * N2, 2, m, dir, 2 * B2, scratch, len,
                                      idx, WORK, tan, 2 * N2),
           DK_ERR_BAD_DIMENSIONS);
    UNTOUCHED(tan, 2 * N2);
}

static void SFX(pipelines_rigid)(void) {
    static REAL p[2 * N2], out[2 * N2], t[2 * N2], r[4 * N2], scratch[WORK], values[WORK];
    static REAL def[2 * B2], nodeq[4 * B2], p3[3 * N3], out3[3 * N3], t3[3 * N3], r3[4 * N3];
    static REAL def3[3 * N3], k2[8 * NC2];
    static uint32_t idx[WORK], nodes1[B2], offs1[B2 + 1], segs1[2 * B2];
    const SFX(dk_spring_system) sys = {grid_graph, k2, graph_len, fixed2, N2};
    REAL q[4], origin[3];
    size_t i, len, vlen;
    SFX(dk_boundary_motion) m;
    dk_spring_solve_options o;
    dk_spring_solve_report rep;

    SFX(grid2)(p);
    SFX(q2)(q);
    for (i = 0; i < B2; i++) {
        double x[2] = {(double)p[2 * perimeter[i]], (double)p[2 * perimeter[i] + 1]}, y[2];
        rigid2(x, y);
        def[2 * i] = (REAL)y[0];
        def[2 * i + 1] = (REAL)y[1];
        memcpy(&nodeq[4 * i], q, sizeof q);
    }

    /* IDW, rotations from the shape (a rigidly moved loop turns every segment by A2). */
    OK(SFX(dk_boundary_motion_default)(&m));
    TRUE_(m.rigid_rotation[0] == 1 && m.nodes_len == 0 && m.index_base == 0 &&
              m.rotation_source == DK_ROTATIONS_SHAPE && m.has_origin == 0,
          "motion default");
    m.nodes = perimeter;
    m.nodes_len = B2;
    m.deformed = def;
    m.deformed_len = 2 * B2;
    m.elements.offsets = seg_offsets;
    m.elements.offsets_len = B2 + 1;
    m.elements.nodes = seg_nodes;
    m.elements.nodes_len = 2 * B2;
    m.elements.kinds = seg_kinds;
    m.elements.kinds_len = B2;
    OK(SFX(dk_boundary_motion_index_scratch_len)(&m, &len));
    TRUE_(len == 0, "index scratch len, base 0");
    OK(dk_deform_idw_scratch_len(N2, B2, 2, &len));
    OK(SFX(dk_deform_idw)(p, 2 * N2, 2, &m, 3, scratch, len, NULL, 0, t, 2 * N2, r, 4 * N2, out,
                          2 * N2, origin, 2));
    SFX(check_rigid)(p, out, N2, 2, perimeter, def, B2, "idw, shape rotations");
    SFX(idw_sensitivities)(p, out, &m);

    /* The same, 1-based. */
    for (i = 0; i < B2; i++) nodes1[i] = perimeter[i] + 1;
    for (i = 0; i <= B2; i++) offs1[i] = seg_offsets[i] + 1;
    for (i = 0; i < 2 * B2; i++) segs1[i] = seg_nodes[i] + 1;
    m.nodes = nodes1;
    m.elements.offsets = offs1;
    m.elements.nodes = segs1;
    m.index_base = 1;
    OK(SFX(dk_boundary_motion_index_scratch_len)(&m, &len));
    TRUE_(len == B2 + B2 + 1 + 2 * B2, "index scratch len, base 1");
    OK(SFX(dk_deform_idw)(p, 2 * N2, 2, &m, 2, scratch, WORK, idx, len, t, 2 * N2, r, 4 * N2,
                          out, 2 * N2, NULL, 0));
    SFX(check_rigid)(p, out, N2, 2, perimeter, def, B2, "idw, 1-based");

    /* TFI over i and j, per-node rotations, origin given. */
    m.rotation_source = DK_ROTATIONS_PER_NODE;
    m.node_rotations = nodeq;
    m.node_rotations_len = 4 * B2;
    m.has_origin = 1;
    m.origin[0] = (REAL)P2[0];
    m.origin[1] = (REAL)P2[1];
    OK(dk_deform_tfi_scratch_len(NX, NY, 1, B2, 2, &len));
    OK(SFX(dk_deform_tfi)(NX, NY, 1, DK_DIRECTION_I | DK_DIRECTION_J, p, 2 * N2, 2, &m, scratch,
                          len, idx, WORK, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin, 2));
    SFX(check_rigid)(p, out, N2, 2, perimeter, def, B2, "tfi, per-node rotations");
    TRUE_(origin[0] == m.origin[0] && origin[1] == m.origin[1], "tfi origin_out = given origin");
    SFX(tfi_sensitivities)(p, &m);

    /* Linear springs, one rigid rotation (quaternion not normalised: scaled by 2). */
    m.rotation_source = DK_ROTATIONS_RIGID;
    for (i = 0; i < 4; i++) m.rigid_rotation[i] = 2 * q[i];
    m.has_origin = 0;
    for (i = 0; i < graph_len; i++) k2[i] = 1;
    OK(SFX(dk_spring_solve_options_default)(&o));
    OK(dk_deform_spring_scratch_len(N2, B2, 2, &o, &len, &vlen));
    TRUE_(len <= WORK && vlen <= WORK, "work buffers large enough");
    OK(SFX(dk_deform_spring_index_scratch_len)(&m, N2, &i));
    TRUE_(i == B2 + B2 + 1 + 2 * B2 + N2, "spring index scratch len");
    OK(SFX(dk_deform_spring)(p, 2 * N2, 2, &m, &sys, &o, scratch, len, values, vlen, idx, i, t,
                             2 * N2, r, 4 * N2, out, 2 * N2, origin, 2, &rep));
    TRUE_(rep.converged, "spring converged");
    SFX(check_rigid)(p, out, N2, 2, perimeter, def, B2, "spring, rigid rotation");

    /* 3D: IDW with one rigid rotation, TFI over i, j, k with per-node rotations. */
    SFX(grid3)(p3);
    SFX(q3)(q);
    for (i = 0; i < nb3; i++) {
        double x[3], y[3];
        int k;
        for (k = 0; k < 3; k++) x[k] = (double)p3[3 * boundary3[i] + k];
        rigid3(x, y);
        for (k = 0; k < 3; k++) def3[3 * i + k] = (REAL)y[k];
    }
    OK(SFX(dk_boundary_motion_default)(&m));
    m.nodes = boundary3;
    m.nodes_len = nb3;
    m.deformed = def3;
    m.deformed_len = 3 * nb3;
    m.rotation_source = DK_ROTATIONS_RIGID;
    memcpy(m.rigid_rotation, q, sizeof q);
    OK(dk_deform_idw_scratch_len(N3, nb3, 3, &len));
    TRUE_(len <= WORK, "work large enough (3D)");
    OK(SFX(dk_deform_idw)(p3, 3 * N3, 3, &m, 2, scratch, len, NULL, 0, t3, 3 * N3, r3, 4 * N3,
                          out3, 3 * N3, origin, 3));
    SFX(check_rigid)(p3, out3, N3, 3, boundary3, def3, nb3, "idw 3D, rigid rotation");
    for (i = 0; i < nb3; i++) memcpy(&values[4 * i], q, sizeof q);
    m.rotation_source = DK_ROTATIONS_PER_NODE;
    m.node_rotations = values;
    m.node_rotations_len = 4 * nb3;
    OK(dk_deform_tfi_scratch_len(MX, MY, MZ, nb3, 3, &len));
    OK(SFX(dk_deform_tfi)(MX, MY, MZ, DK_DIRECTION_I | DK_DIRECTION_J | DK_DIRECTION_K, p3,
                          3 * N3, 3, &m, scratch, len, NULL, 0, t3, 3 * N3, r3, 4 * N3, out3,
                          3 * N3, NULL, 0));
    SFX(check_rigid)(p3, out3, N3, 3, boundary3, def3, nb3, "tfi 3D, per-node rotations");
}

/* Bad input to the pipelines: the documented status, and out / origin_out untouched. */
static void SFX(pipelines_bad)(void) {
    static REAL p[2 * N2], out[2 * N2], t[2 * N2], r[4 * N2], scratch[WORK], values[WORK];
    static REAL def[2 * B2], k2[8 * NC2];
    static uint32_t idx[WORK], nodes[B2];
    const SFX(dk_spring_system) sys = {grid_graph, k2, graph_len, fixed2, N2};
    REAL origin[2] = {SENTINEL, SENTINEL}, zeroq[4] = {0, 0, 0, 0};
    size_t i, len;
    SFX(dk_boundary_motion) m, bad;
    dk_spring_solve_options o;
    dk_spring_solve_report rep;

    SFX(grid2)(p);
    for (i = 0; i < B2; i++) {
        def[2 * i] = p[2 * perimeter[i]] + (REAL)0.01;
        def[2 * i + 1] = p[2 * perimeter[i] + 1];
    }
    FILL(out, 2 * N2);
    rep.iterations = SENTINEL;
    OK(SFX(dk_boundary_motion_default)(&m));
    m.nodes = perimeter;
    m.nodes_len = B2;
    m.deformed = def;
    m.deformed_len = 2 * B2;
    m.elements.offsets = seg_offsets;
    m.elements.offsets_len = B2 + 1;
    m.elements.nodes = seg_nodes;
    m.elements.nodes_len = 2 * B2;
    m.elements.kinds = seg_kinds;
    m.elements.kinds_len = B2;
    len = WORK;

#define IDW(motion, exp, olen) \
    SFX(dk_deform_idw)(p, 2 * N2, 2, motion, exp, scratch, len, idx, WORK, t, 2 * N2, r, \
                       4 * N2, out, olen, origin, 2)
    EXPECT(SFX(dk_deform_idw)(NULL, 2 * N2, 2, &m, 2, scratch, len, idx, WORK, t, 2 * N2, r,
                              4 * N2, out, 2 * N2, origin, 2),
           DK_ERR_NULL_POINTER);
    EXPECT(IDW(NULL, 2, 2 * N2), DK_ERR_NULL_POINTER);
    EXPECT(IDW(&m, 2, 2 * N2 - 2), DK_ERR_LENGTH_MISMATCH);
    EXPECT(IDW(&m, 2, 2 * N2 - 1), DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_idw)(p, 2 * N2, 4, &m, 2, scratch, len, idx, WORK, t, 2 * N2, r,
                              4 * N2, out, 2 * N2, origin, 2),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_deform_idw)(p, 2 * N2, 2, &m, 2, scratch, len, idx, WORK, t, 2 * N2, r,
                              4 * N2, out, 2 * N2, origin, 3),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_idw)(p, 2 * N2, 2, &m, 2, scratch, 10, idx, WORK, t, 2 * N2, r,
                              4 * N2, out, 2 * N2, origin, 2),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(IDW(&m, (REAL)NAN, 2 * N2), DK_ERR_INVALID_PARAMETER);
    EXPECT(IDW(&m, -1, 2 * N2), DK_ERR_INVALID_PARAMETER);
    bad = m;
    memcpy(nodes, perimeter, sizeof nodes);
    bad.nodes = nodes;
    nodes[3] = N2; /* out of range */
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_INDEX_OUT_OF_RANGE);
    nodes[3] = nodes[4]; /* duplicate */
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_DUPLICATE_NODE);
    bad = m;
    bad.index_base = 2;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_BAD_INDEX_BASE);
    bad.index_base = 1; /* offset 0 is not 1-based */
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_BAD_OFFSETS);
    EXPECT(SFX(dk_deform_idw)(p, 2 * N2, 2, &bad, 2, scratch, len, idx, B2, t, 2 * N2, r,
                              4 * N2, out, 2 * N2, origin, 2),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(SFX(dk_deform_idw)(p, 2 * N2, 2, &bad, 2, scratch, len, NULL, WORK, t, 2 * N2, r,
                              4 * N2, out, 2 * N2, origin, 2),
           DK_ERR_NULL_POINTER);
    /* Without elements (one rigid rotation): node 0 is not 1-based; a boundary whose
     * deformed positions do not match its length. */
    bad = m;
    bad.elements.offsets_len = 0;
    bad.elements.nodes_len = 0;
    bad.elements.kinds_len = 0;
    bad.rotation_source = DK_ROTATIONS_RIGID;
    bad.index_base = 1;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_INDEX_OUT_OF_RANGE);
    bad.index_base = 0;
    bad.nodes_len = B2 - 1;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_LENGTH_MISMATCH);
    bad = m;
    bad.nodes = NULL;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_NULL_POINTER);
    bad.nodes_len = 0;
    bad.deformed_len = 0;
    bad.elements.offsets_len = 0;
    bad.elements.nodes_len = 0;
    bad.elements.kinds_len = 0;
    bad.rotation_source = DK_ROTATIONS_RIGID;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_INVALID_PARAMETER); /* empty boundary */
    bad = m;
    bad.rotation_source = 7;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_INVALID_PARAMETER);
    bad.rotation_source = DK_ROTATIONS_SHAPE;
    bad.elements.offsets_len = 0;
    bad.elements.nodes_len = 0;
    bad.elements.kinds_len = 0;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_INVALID_PARAMETER); /* shape without elements */
    bad = m;
    bad.rotation_source = DK_ROTATIONS_RIGID;
    memcpy(bad.rigid_rotation, zeroq, sizeof zeroq);
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_ZERO_LENGTH);
    bad.rigid_rotation[0] = (REAL)NAN;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_NON_FINITE);
    bad = m;
    bad.rotation_source = DK_ROTATIONS_PER_NODE;
    bad.node_rotations = values;
    bad.node_rotations_len = 4 * B2 - 4;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_LENGTH_MISMATCH);
    bad = m;
    bad.has_origin = 1;
    bad.origin[1] = (REAL)INFINITY;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_NON_FINITE);
    bad = m;
    bad.elements.kinds_len = B2 - 1;
    EXPECT(IDW(&bad, 2, 2 * N2), DK_ERR_LENGTH_MISMATCH);
    def[5] = (REAL)NAN;
    EXPECT(IDW(&m, 2, 2 * N2), DK_ERR_NON_FINITE);
    def[5] = p[2 * perimeter[2] + 1];
    p[2 * 8] = (REAL)NAN;
    EXPECT(IDW(&m, 2, 2 * N2), DK_ERR_NON_FINITE);
    SFX(grid2)(p);
#undef IDW
    UNTOUCHED(out, 2 * N2);
    UNTOUCHED(origin, 2);

    /* TFI: an unlisted face point, bad directions, bad block. */
    bad = m;
    bad.elements.offsets_len = 0;
    bad.elements.nodes_len = 0;
    bad.elements.kinds_len = 0;
    bad.rotation_source = DK_ROTATIONS_RIGID;
    bad.nodes_len = B2 - 1;
    bad.deformed_len = 2 * (B2 - 1);
    EXPECT(SFX(dk_deform_tfi)(NX, NY, 1, DK_DIRECTION_I | DK_DIRECTION_J, p, 2 * N2, 2, &bad,
                              scratch, WORK, idx, WORK, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin,
                              2),
           DK_ERR_UNANCHORED);
    EXPECT(SFX(dk_deform_tfi)(NX, NY, 1, 8, p, 2 * N2, 2, &m, scratch, WORK, idx, WORK, t, 2 * N2,
                              r, 4 * N2, out, 2 * N2, origin, 2),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_deform_tfi)(NX, NY, 1, DK_DIRECTION_K, p, 2 * N2, 2, &m, scratch, WORK, idx,
                              WORK, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin, 2),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_deform_tfi)(NX, 0, 1, DK_DIRECTION_I, p, 2 * N2, 2, &m, scratch, WORK, idx,
                              WORK, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin, 2),
           DK_ERR_BAD_DIMENSIONS);
    EXPECT(SFX(dk_deform_tfi)(NX, NY + 1, 1, DK_DIRECTION_I, p, 2 * N2, 2, &m, scratch, WORK,
                              idx, WORK, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin, 2),
           DK_ERR_LENGTH_MISMATCH);
    UNTOUCHED(out, 2 * N2);
    UNTOUCHED(origin, 2);

    /* Springs: a fixed mask that is not the boundary, bad options, asymmetric stiffness. */
    for (i = 0; i < graph_len; i++) k2[i] = 1;
    OK(SFX(dk_spring_solve_options_default)(&o));
    fixed2[NX + 1] = 1; /* an interior node */
    EXPECT(SFX(dk_deform_spring)(p, 2 * N2, 2, &m, &sys, &o, scratch, WORK, values, WORK, idx,
                                 WORK, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin, 2, &rep),
           DK_ERR_INVALID_PARAMETER);
    fixed2[NX + 1] = 0;
    o.omega = 3;
    o.preconditioner = DK_PRECONDITIONER_SSOR;
    EXPECT(SFX(dk_deform_spring)(p, 2 * N2, 2, &m, &sys, &o, scratch, WORK, values, WORK, idx,
                                 WORK, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin, 2, &rep),
           DK_ERR_INVALID_PARAMETER);
    OK(SFX(dk_spring_solve_options_default)(&o));
    k2[0] = 2;
    EXPECT(SFX(dk_deform_spring)(p, 2 * N2, 2, &m, &sys, &o, scratch, WORK, values, WORK, idx,
                                 WORK, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin, 2, &rep),
           DK_ERR_NOT_SYMMETRIC);
    k2[0] = 1;
    EXPECT(SFX(dk_deform_spring)(p, 2 * N2, 2, &m, &sys, &o, scratch, WORK, values, WORK, idx,
                                 N2 - 1, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin, 2, &rep),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(SFX(dk_deform_spring)(p, 2 * N2, 2, &m, &sys, &o, scratch, WORK, values, 10, idx,
                                 WORK, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin, 2, &rep),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(SFX(dk_deform_spring)(p, 2 * N2, 2, &m, &sys, &o, scratch, WORK, values, WORK, idx,
                                 WORK, t, 2 * N2, r, 4 * N2, out, 2 * N2, origin, 2, NULL),
           DK_ERR_NULL_POINTER);
    UNTOUCHED(out, 2 * N2);
    UNTOUCHED(origin, 2);
    TRUE_(rep.iterations == SENTINEL, "spring report written on error");
}

/* The building blocks, checked independently, and with bad input. */
static void SFX(blocks)(void) {
    /* A unit square, counter-clockwise, and the same square moved rigidly. */
    REAL sq[8] = {0, 0, 1, 0, 1, 1, 0, 1}, moved[8], normals[8], rot[16], sc[64], q[4];
    REAL origin[2], trans[8], back[8], zero4[4] = {0, 0, 0, 0}, nanp[8];
    uint32_t so[5] = {0, 2, 4, 6, 8}, sn[8] = {0, 1, 1, 2, 2, 3, 3, 0}, idx[64];
    uint32_t so1[5] = {1, 3, 5, 7, 9}, sn1[8] = {1, 2, 2, 3, 3, 4, 4, 1};
    uint8_t sk[4] = {3, 3, 3, 3};
    /* The square's boundary loop as four segments, 0- and 1-based; `bad` for broken copies. */
    const dk_cells loop = {so, 5, sn, 8, sk, 4}, loop1 = {so1, 5, sn1, 8, sk, 4};
    dk_cells bad;
    static REAL p[2 * N2], t[2 * N2], r[4 * N2], out[2 * N2], scratch[WORK], values[WORK];
    static REAL def[2 * B2], k2[8 * NC2];
    static uint32_t nodes1[B2], sidx[N2];
    REAL cube[24], cubed[24], crot[32], csc[13 * 8];
    uint32_t co[7] = {0, 4, 8, 12, 16, 20, 24};
    uint32_t cn[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 2, 3, 7, 6, 1, 2, 6, 5, 0, 4, 7, 3};
    uint8_t ck[6] = {9, 9, 9, 9, 9, 9};
    const dk_cells faces = {co, 7, cn, 24, ck, 6}; /* the cube's six quads */
    const SFX(dk_spring_system) sys = {grid_graph, k2, graph_len, fixed2, N2};
    const double h = sqrt(0.5);
    size_t i, len;
    int k;
    dk_spring_solve_options o;
    dk_spring_solve_report rep;

    /* Normals: corners (+-1, +-1)/sqrt(2), outward. */
    OK(SFX(dk_deform_boundary_normals)(sq, 8, 2, &loop, 0, sc, 12, NULL, 0, normals, 8));
    NEAR(normals[0], -h, "normal 0 x");
    NEAR(normals[1], -h, "normal 0 y");
    NEAR(normals[4], h, "normal 2 x");
    NEAR(normals[5], h, "normal 2 y");
    NEAR(normals[6], -h, "normal 3 x");
    NEAR(normals[7], h, "normal 3 y");
    FILL(normals, 8);
    OK(SFX(dk_deform_boundary_normals)(sq, 8, 2, &loop1, 1, sc, 12, idx, 13, normals, 8));
    NEAR(normals[2], h, "normal 1 x, 1-based elements");
    NEAR(normals[3], -h, "normal 1 y, 1-based elements");
    FILL(normals, 8);
    EXPECT(SFX(dk_deform_boundary_normals)(sq, 8, 2, &loop1, 1, sc, 12, idx, 12, normals, 8),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(SFX(dk_deform_boundary_normals)(sq, 8, 2, &loop, 0, sc, 11, NULL, 0, normals, 8),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(SFX(dk_deform_boundary_normals)(sq, 8, 2, &loop, 0, sc, 12, NULL, 0, normals, 6),
           DK_ERR_LENGTH_MISMATCH);
    bad = (dk_cells){so, 3, sn, 4, sk, 2}; /* two segments: node 3 on none */
    EXPECT(SFX(dk_deform_boundary_normals)(sq, 8, 2, &bad, 0, sc, 12, NULL, 0, normals, 8),
           DK_ERR_ISOLATED_NODE);
    bad = (dk_cells){so, 0, NULL, 0, NULL, 0};
    EXPECT(SFX(dk_deform_boundary_normals)(sq, 8, 2, &bad, 0, sc, 12, NULL, 0, normals, 8),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_boundary_normals)(sq, 8, 3, &loop, 0, sc, 12, NULL, 0, normals, 8),
           DK_ERR_LENGTH_MISMATCH); /* 8 scalars are not 3D points */
    memcpy(nanp, sq, sizeof sq);
    nanp[3] = (REAL)NAN;
    EXPECT(SFX(dk_deform_boundary_normals)(nanp, 8, 2, &loop, 0, sc, 12, NULL, 0, normals, 8),
           DK_ERR_NON_FINITE);
    EXPECT(SFX(dk_deform_boundary_normals)(sq, 8, 2, &loop, 2, sc, 12, NULL, 0, normals, 8),
           DK_ERR_BAD_INDEX_BASE);
    UNTOUCHED(normals, 8);

    /* Rotations from the shape: a rigidly moved square turns by A2 at every node. */
    for (i = 0; i < 4; i++) {
        double x[2] = {(double)sq[2 * i], (double)sq[2 * i + 1]}, y[2];
        rigid2(x, y);
        moved[2 * i] = (REAL)y[0];
        moved[2 * i + 1] = (REAL)y[1];
    }
    SFX(q2)(q);
    OK(SFX(dk_deform_boundary_rotations)(sq, 8, moved, 8, 2, &loop, 0, sc, 12, NULL, 0, rot, 16));
    for (i = 0; i < 4; i++)
        for (k = 0; k < 4; k++) NEAR(rot[4 * i + k], q[k], "2D shape rotation");
    FILL(rot, 16);
    EXPECT(SFX(dk_deform_boundary_rotations)(sq, 8, sq, 6, 2, &loop, 0, sc, 12, NULL, 0, rot, 16),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_boundary_rotations)(sq, 8, moved, 8, 2, &loop, 0, sc, 11, NULL, 0, rot,
                                             16),
           DK_ERR_BUFFER_TOO_SMALL);
    memcpy(nanp, moved, sizeof moved);
    nanp[2] = nanp[0];
    nanp[3] = nanp[1]; /* node 1 on node 0: a zero-length segment */
    EXPECT(SFX(dk_deform_boundary_rotations)(sq, 8, nanp, 8, 2, &loop, 0, sc, 12, NULL, 0, rot,
                                             16),
           DK_ERR_ZERO_LENGTH_EDGE);
    bad = loop;
    bad.kinds = ck;
    EXPECT(SFX(dk_deform_boundary_rotations)(sq, 8, moved, 8, 2, &bad, 0, sc, 12, NULL, 0, rot,
                                             16),
           DK_ERR_WRONG_NODE_COUNT); /* quads with two nodes each */
    UNTOUCHED(rot, 16);

    /* 3D: a unit cube's six outward quads, rotated rigidly: every node gets q (up to sign). */
    for (i = 0; i < 8; i++) {
        double x[3] = {(double)(i & 1 ? 1 : 0), (double)(i & 2 ? 1 : 0), (double)(i & 4 ? 1 : 0)},
               y[3];
        /* renumber to the usual hex order: 0 1 3 2 / 4 5 7 6 */
        size_t v = (i & 4) | ((i & 2) ? ((i & 1) ? 2 : 3) : (i & 1));
        rigid3(x, y);
        for (k = 0; k < 3; k++) {
            cube[3 * v + k] = (REAL)x[k];
            cubed[3 * v + k] = (REAL)y[k];
        }
    }
    SFX(q3)(q);
    OK(dk_deform_boundary_rotations_scratch_len(8, 3, &len));
    OK(SFX(dk_deform_boundary_rotations)(cube, 24, cubed, 24, 3, &faces, 0, csc, len, NULL, 0,
                                         crot, 32));
    for (i = 0; i < 8; i++) {
        double sgn = crot[4 * i] * q[0] < 0 ? -1.0 : 1.0;
        for (k = 0; k < 4; k++) NEAR(sgn * crot[4 * i + k], q[k], "3D shape rotation");
    }
    EXPECT(SFX(dk_deform_boundary_normals)(cube, 24, 3, &loop, 0, csc, 24, NULL, 0, crot, 24),
           DK_ERR_CELL_DIMENSION); /* segments are not 3D boundary elements */

    /* Rigid rotations: normalised copies. */
    for (k = 0; k < 4; k++) q[k] = (REAL)(k + 1);
    OK(SFX(dk_deform_rigid_rotations)(q, rot, 12));
    for (i = 0; i < 3; i++)
        for (k = 0; k < 4; k++) NEAR(rot[4 * i + k], (k + 1) / sqrt(30.0), "rigid rotations");
    FILL(rot, 16);
    EXPECT(SFX(dk_deform_rigid_rotations)(zero4, rot, 12), DK_ERR_ZERO_LENGTH);
    EXPECT(SFX(dk_deform_rigid_rotations)(q, rot, 10), DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_rigid_rotations)(NULL, rot, 12), DK_ERR_NULL_POINTER);
    EXPECT(SFX(dk_deform_rigid_rotations)(q, NULL, 12), DK_ERR_NULL_POINTER);
    q[2] = (REAL)NAN;
    EXPECT(SFX(dk_deform_rigid_rotations)(q, rot, 12), DK_ERR_NON_FINITE);
    UNTOUCHED(rot, 16);

    /* Origin: the centroid of the points that move (nodes 1 and 2 here). */
    memcpy(nanp, sq, sizeof sq);
    nanp[2] += 1;
    nanp[5] += 1;
    OK(SFX(dk_deform_boundary_origin)(sq, 8, nanp, 8, 2, origin, 2));
    NEAR(origin[0], 1.0, "origin x");
    NEAR(origin[1], 0.5, "origin y");
    FILL(origin, 2);
    EXPECT(SFX(dk_deform_boundary_origin)(sq, 8, nanp, 8, 2, origin, 3), DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_boundary_origin)(sq, 8, nanp, 6, 2, origin, 2), DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_boundary_origin)(sq, 0, nanp, 0, 2, origin, 2),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_deform_boundary_origin)(sq, 8, nanp, 8, 2, NULL, 2), DK_ERR_NULL_POINTER);
    nanp[7] = (REAL)NAN;
    EXPECT(SFX(dk_deform_boundary_origin)(sq, 8, nanp, 8, 2, origin, 2), DK_ERR_NON_FINITE);
    UNTOUCHED(origin, 2);

    /* Translations: o + delta + Q (u - o) Q* reproduces the deformed points; update_points
     * with those values (and no boundary list) then moves the square onto them. */
    SFX(q2)(q);
    for (i = 0; i < 4; i++) memcpy(&rot[4 * i], q, sizeof q);
    origin[0] = (REAL)P2[0];
    origin[1] = (REAL)P2[1];
    OK(SFX(dk_deform_boundary_translations)(origin, 2, sq, 8, moved, 8, 2, rot, 16, trans, 8));
    OK(SFX(dk_deform_update_points)(origin, 2, sq, 8, 2, trans, 8, rot, 16, NULL, 0, 0, NULL, 0,
                                    NULL, 0, back, 8));
    for (i = 0; i < 8; i++) NEAR(back[i], moved[i], "translations + update reproduce r^d");
    for (i = 0; i < 8; i++) NEAR(trans[i], T2[i % 2], "rigid translation about the pivot");
    FILL(trans, 8);
    EXPECT(SFX(dk_deform_boundary_translations)(origin, 1, sq, 8, moved, 8, 2, rot, 16, trans, 8),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_boundary_translations)(origin, 2, sq, 8, moved, 8, 2, rot, 12, trans, 8),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_boundary_translations)(origin, 2, sq, 8, moved, 8, 2, zero4, 4, trans,
                                                2),
           DK_ERR_LENGTH_MISMATCH);
    rot[5] = (REAL)NAN;
    EXPECT(SFX(dk_deform_boundary_translations)(origin, 2, sq, 8, moved, 8, 2, rot, 16, trans, 8),
           DK_ERR_NON_FINITE);
    memset(rot + 4, 0, 4 * sizeof(REAL));
    EXPECT(SFX(dk_deform_boundary_translations)(origin, 2, sq, 8, moved, 8, 2, rot, 16, trans, 8),
           DK_ERR_ZERO_LENGTH);
    UNTOUCHED(trans, 8);

    /* IDW / TFI / spring propagation of a uniform (delta, Q) reproduce it; update_points puts
     * the boundary nodes exactly at their prescribed positions (1-based list). */
    SFX(grid2)(p);
    SFX(q3)(q);
    for (i = 0; i < N2; i++) {
        t[2 * i] = (REAL)0.25;
        t[2 * i + 1] = (REAL)-0.5;
        memcpy(&r[4 * i], q, sizeof q);
    }
    for (i = 0; i < B2; i++) nodes1[i] = perimeter[i] + 1;
    OK(SFX(dk_deform_propagate_idw)(p, 2 * N2, 2, nodes1, B2, 1, 2, sidx, B2, t, 2 * N2, r,
                                    4 * N2));
    for (i = 0; i < N2; i++) {
        NEAR(t[2 * i], 0.25, "idw uniform translation");
        NEAR(t[2 * i + 1], -0.5, "idw uniform translation");
        for (k = 0; k < 4; k++) NEAR(r[4 * i + k], q[k], "idw uniform rotation");
    }
    OK(dk_deform_propagate_tfi_scratch_len(NX, NY, 1, 2, &len));
    OK(SFX(dk_deform_propagate_tfi)(NX, NY, 1, DK_DIRECTION_I | DK_DIRECTION_J, p, 2 * N2, 2,
                                    scratch, len, t, 2 * N2, r, 4 * N2));
    for (i = 0; i < N2; i++) {
        NEAR(t[2 * i], 0.25, "tfi uniform translation");
        for (k = 0; k < 4; k++) NEAR(r[4 * i + k], q[k], "tfi uniform rotation");
    }
    OK(SFX(dk_deform_displacement_tfi)(NX, NY, 1, DK_DIRECTION_J, p, 2 * N2, 2, scratch, len, t,
                                       2 * N2));
    for (i = 0; i < N2; i++) NEAR(t[2 * i + 1], -0.5, "displacement tfi uniform");
    for (i = 0; i < graph_len; i++) k2[i] = 1;
    OK(SFX(dk_spring_solve_options_default)(&o));
    OK(dk_deform_propagate_spring_scratch_len(N2, 2, &o, &len));
    OK(SFX(dk_deform_propagate_spring)(&sys, &o, 2, sidx, N2, values, len, t, 2 * N2, r, 4 * N2,
                                       &rep));
    TRUE_(rep.converged, "propagate spring converged");
    for (i = 0; i < N2; i++) {
        NEAR(t[2 * i + 1], -0.5, "spring uniform translation");
        for (k = 0; k < 4; k++) NEAR(r[4 * i + k], q[k], "spring uniform rotation");
    }
    for (i = 0; i < B2; i++) {
        def[2 * i] = p[2 * perimeter[i]] + (REAL)1e-3 * (REAL)i;
        def[2 * i + 1] = -p[2 * perimeter[i] + 1];
    }
    origin[0] = 0;
    origin[1] = 0;
    OK(SFX(dk_deform_update_points)(origin, 2, p, 2 * N2, 2, t, 2 * N2, r, 4 * N2, nodes1, B2, 1,
                                    def, 2 * B2, sidx, B2, out, 2 * N2));
    for (i = 0; i < B2; i++)
        TRUE_(memcmp(&out[2 * perimeter[i]], &def[2 * i], 2 * sizeof(REAL)) == 0,
              "update_points: boundary not bitwise prescribed");

    /* Bad input to the field-level blocks: values and out untouched. */
    FILL(t, 2 * N2);
    FILL(r, 4 * N2);
    FILL(out, 2 * N2);
    r[0] = 1; /* a valid boundary rotation at node 0, sentinels elsewhere */
    EXPECT(SFX(dk_deform_propagate_idw)(p, 2 * N2, 2, nodes1, B2, 1, 2, sidx, B2 - 1, t, 2 * N2,
                                        r, 4 * N2),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(SFX(dk_deform_propagate_idw)(p, 2 * N2, 2, nodes1, B2, 0, 2, sidx, 0, t, 2 * N2, r,
                                        4 * N2),
           DK_ERR_INDEX_OUT_OF_RANGE); /* node N2 read 0-based */
    EXPECT(SFX(dk_deform_propagate_idw)(p, 2 * N2, 2, nodes1, B2, 1, 0, sidx, B2, t, 2 * N2, r,
                                        4 * N2),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_deform_propagate_idw)(p, 2 * N2, 2, nodes1, B2, 1, 2, sidx, B2, t, 2 * N2, r,
                                        4 * N2 - 4),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_propagate_tfi)(NX, NY, 1, DK_DIRECTION_I, p, 2 * N2, 2, scratch, 10, t,
                                        2 * N2, r, 4 * N2),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(SFX(dk_deform_propagate_tfi)(NX, NY, 1, 0, p, 2 * N2, 2, scratch, WORK, t, 2 * N2, r,
                                        4 * N2),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(SFX(dk_deform_displacement_tfi)(NX, NY, 2, DK_DIRECTION_I, p, 2 * N2, 2, scratch,
                                           WORK, t, 2 * N2),
           DK_ERR_BAD_DIMENSIONS);
    EXPECT(SFX(dk_deform_displacement_tfi)(NX, NY, 1, DK_DIRECTION_I, p, 2 * N2, 2, scratch,
                                           WORK, NULL, 2 * N2),
           DK_ERR_NULL_POINTER);
    UNTOUCHED(t, 2 * N2);
    UNTOUCHED(r + 4, 4 * N2 - 4);
    r[0] = SENTINEL;
    memset(r + 4, 0, 4 * sizeof(REAL)); /* a zero rotation at fixed node 1 */
    EXPECT(SFX(dk_deform_propagate_spring)(&sys, &o, 2, sidx, N2, values, len, t, 2 * N2, r,
                                           4 * N2, &rep),
           DK_ERR_ZERO_LENGTH);
    FILL(r, 4 * N2);
    k2[3] = 0;
    EXPECT(SFX(dk_deform_propagate_spring)(&sys, &o, 2, sidx, N2, values, len, t, 2 * N2, r,
                                           4 * N2, &rep),
           DK_ERR_NON_POSITIVE);
    k2[3] = 1;
    EXPECT(SFX(dk_deform_propagate_spring)(&sys, &o, 4, sidx, N2, values, len, t, 2 * N2, r,
                                           4 * N2, &rep),
           DK_ERR_INVALID_PARAMETER);
    UNTOUCHED(t, 2 * N2);
    UNTOUCHED(r, 4 * N2);
    SFX(q3)(q);
    for (i = 0; i < N2; i++) memcpy(&r[4 * i], q, sizeof q);
    for (i = 0; i < 2 * N2; i++) t[i] = 0;
    EXPECT(SFX(dk_deform_update_points)(origin, 2, p, 2 * N2, 2, t, 2 * N2, r, 4 * N2, nodes1, B2,
                                        1, def, 2 * B2 - 2, sidx, B2, out, 2 * N2),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(SFX(dk_deform_update_points)(origin, 2, p, 2 * N2, 2, t, 2 * N2, r, 4 * N2, nodes1, B2,
                                        2, def, 2 * B2, sidx, B2, out, 2 * N2),
           DK_ERR_BAD_INDEX_BASE);
    t[7] = (REAL)NAN;
    EXPECT(SFX(dk_deform_update_points)(origin, 2, p, 2 * N2, 2, t, 2 * N2, r, 4 * N2, nodes1, B2,
                                        1, def, 2 * B2, sidx, B2, out, 2 * N2),
           DK_ERR_NON_FINITE);
    t[7] = 0;
    memset(r + 8, 0, 4 * sizeof(REAL));
    EXPECT(SFX(dk_deform_update_points)(origin, 2, p, 2 * N2, 2, t, 2 * N2, r, 4 * N2, nodes1, B2,
                                        1, def, 2 * B2, sidx, B2, out, 2 * N2),
           DK_ERR_ZERO_LENGTH);
    UNTOUCHED(out, 2 * N2);
}

static void SFX(generic_tests)(void) {
    SFX(pipelines_rigid)();
    SFX(pipelines_bad)();
    SFX(blocks)();
}

#undef NEAR
#endif

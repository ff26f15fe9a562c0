/* Tangent and adjoint of multi-step elasticity from C99: dk_elasticity_sensitivity_scratch_len,
 * dk_elasticity_tangent and dk_elasticity_adjoint (and their _f32 twins) on a 5 x 5 node
 * square of triangles, its interior jittered, whose boundary turns and bends (a nonlinear
 * map) in 3 increments with inverse-volume moduli: double with 0-based cells, float with
 * 1-based ones.
 *
 * Checks here: the dot-product identity <J v, w> = <v, J^T w> (both precisions), the tangent
 * against central differences of dk_elasticity_deform, the tangent exactly v at fixed nodes
 * and the adjoint zero at free nodes, and bad input (short scratch, dim 4, 0 steps) that
 * returns its status and leaves dx and g untouched. Prints the inputs and the f64 results'
 * bits, which host-tests/tests/ffi/c_abi_elasticity_sensitivity.rs recomputes with the
 * kernel. Ends with "elasticity_sensitivity: every check held" (exit 0), or prints each
 * failed check (exit 1). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

#define S 5
#define N (S * S)
#define NT (2 * (S - 1) * (S - 1))

static uint32_t toffs[NT + 1], toffs1[NT + 1], tnodes[3 * NT], tnodes1[3 * NT];
static uint8_t tkinds[NT];
static double pts[2 * N], dsp[2 * N], v[2 * N], w[2 * N];
static uint8_t fix[N];

/* Two triangles per square; the boundary moves by a turn and a bend; v on the boundary and
 * w everywhere from fixed formulas. */
static void mesh(void) {
    size_t i, j, c = 0;
    for (j = 0; j < S; j++) {
        for (i = 0; i < S; i++) {
            size_t n = i + S * j;
            int edge = i == 0 || j == 0 || i == S - 1 || j == S - 1;
            double x = ((double)i + (edge ? 0.0 : 0.1 * sin(3.0 * (double)n))) / (S - 1);
            double y = ((double)j + (edge ? 0.0 : 0.1 * cos(5.0 * (double)n))) / (S - 1);
            pts[2 * n] = x;
            pts[2 * n + 1] = y;
            fix[n] = (uint8_t)edge;
            dsp[2 * n] = edge ? -0.3 * (y - 0.5) + 0.1 * x * y : 0.0;
            dsp[2 * n + 1] = edge ? 0.3 * (x - 0.5) - 0.05 * x * x : 0.0;
            v[2 * n] = edge ? sin(1.0 + (double)n) : 0.0;
            v[2 * n + 1] = edge ? cos(2.0 * (double)n) : 0.0;
            w[2 * n] = sin(0.7 * (double)n);
            w[2 * n + 1] = cos(1.3 * (double)n + 0.5);
        }
    }
    toffs[0] = 0;
    for (j = 0; j + 1 < S; j++) {
        for (i = 0; i + 1 < S; i++) {
            uint32_t a = (uint32_t)(i + S * j);
            uint32_t t[6] = {a, a + 1, a + 1 + S, a, a + 1 + S, a + S};
            memcpy(tnodes + 3 * c, t, sizeof t);
            tkinds[c] = tkinds[c + 1] = 5;
            toffs[c + 1] = (uint32_t)(3 * c + 3);
            toffs[c + 2] = (uint32_t)(3 * c + 6);
            c += 2;
        }
    }
    for (i = 0; i < 3 * NT; i++) tnodes1[i] = tnodes[i] + 1;
    for (i = 0; i <= NT; i++) toffs1[i] = toffs[i] + 1;
}

static double dot(const double *a, const double *b) {
    double s = 0.0;
    size_t k;
    for (k = 0; k < 2 * N; k++) s += a[k] * b[k];
    return s;
}

static double dotf(const float *a, const float *b) {
    double s = 0.0;
    size_t k;
    for (k = 0; k < 2 * N; k++) s += (double)a[k] * (double)b[k];
    return s;
}

/* |<jv, w> - <v, g>| / (|jv| |w|). */
static double identity(double jvw, double vg, double jj, double ww) {
    return fabs(jvw - vg) / sqrt(jj * ww);
}

int main(void) {
    uint32_t offsets[N + 1], *targets, iscr[NT + 1 + 3 * NT];
    size_t tlen, used, slen, k;
    dk_cells cells, cells1;
    dk_graph graph;
    dk_elasticity_options o, o32;
    dk_elasticity_report r;
    double *scratch, jv[2 * N], g[2 * N], plus[2 * N], minus[2 * N], keep[2 * N];
    double h = 1e-5, err = 0.0, scale = 0.0;
    float *scratch32, p32[2 * N], d32[2 * N], jv32[2 * N], g32[2 * N], w32[2 * N], v32[2 * N];
    mesh();
    cells.offsets = toffs;
    cells.offsets_len = NT + 1;
    cells.nodes = tnodes;
    cells.nodes_len = 3 * NT;
    cells.kinds = tkinds;
    cells.kinds_len = NT;
    cells1 = cells;
    cells1.offsets = toffs1;
    cells1.nodes = tnodes1;
    OK(dk_elasticity_graph_len(N, &cells, 0, NULL, 0, &tlen));
    targets = xmalloc(tlen * sizeof *targets);
    OK(dk_elasticity_graph(N, &cells, 0, NULL, 0, offsets, N + 1, targets, tlen, &used));
    graph.offsets = offsets;
    graph.offsets_len = N + 1;
    graph.targets = targets;
    graph.targets_len = used;
    OK(dk_elasticity_sensitivity_scratch_len(N, NT, used, 2, 3, &slen));
    scratch = xmalloc(slen * sizeof *scratch);
    scratch32 = xmalloc(slen * sizeof *scratch32);
    hex64("points", pts, 2 * N);
    hex64("disp", dsp, 2 * N);
    hex64("v", v, 2 * N);
    hex64("w", w, 2 * N);

    OK(dk_elasticity_options_default(&o));
    o.steps = 3;
    o.residual_tol = 1e-13;
    memcpy(jv, v, sizeof jv);
    OK(dk_elasticity_tangent(&cells, 0, NULL, 0, &graph, 2, fix, N, &o, NULL, 0, pts, 2 * N,
                             dsp, 2 * N, jv, 2 * N, scratch, slen, &r));
    CHECK(r.converged && r.steps == 3);
    OK(dk_elasticity_adjoint(&cells, 0, NULL, 0, &graph, 2, fix, N, &o, NULL, 0, pts, 2 * N,
                             dsp, 2 * N, w, 2 * N, g, 2 * N, scratch, slen, &r));
    CHECK(r.converged && r.steps == 3);
    hex64("jv", jv, 2 * N);
    hex64("g", g, 2 * N);
    CHECK(identity(dot(jv, w), dot(v, g), dot(jv, jv), dot(w, w)) <= 1e-11);
    for (k = 0; k < 2 * N; k++) {
        if (fix[k / 2]) CHECK(jv[k] == v[k]);
        else CHECK(g[k] == 0.0);
    }
    /* Central differences of the deformation along v. */
    for (k = 0; k < 2 * N; k++) {
        plus[k] = dsp[k] + h * v[k];
        minus[k] = dsp[k] - h * v[k];
    }
    memcpy(keep, pts, sizeof keep);
    OK(dk_elasticity_deform(&cells, 0, NULL, 0, &graph, 2, fix, N, &o, NULL, 0, plus, 2 * N,
                            keep, 2 * N, scratch, slen, &r));
    memcpy(plus, keep, sizeof keep);
    memcpy(keep, pts, sizeof keep);
    OK(dk_elasticity_deform(&cells, 0, NULL, 0, &graph, 2, fix, N, &o, NULL, 0, minus, 2 * N,
                            keep, 2 * N, scratch, slen, &r));
    for (k = 0; k < 2 * N; k++) {
        double fd = (plus[k] - keep[k]) / (2.0 * h);
        err = fmax(err, fabs(fd - jv[k]));
        scale = fmax(scale, fabs(jv[k]));
    }
    printf("central differences: relative error %.1e\n", err / scale);
    CHECK(err <= 1e-6 * scale);

    OK(dk_elasticity_options_default_f32(&o32));
    o32.steps = 3;
    o32.residual_tol = 1e-6;
    for (k = 0; k < 2 * N; k++) {
        p32[k] = (float)pts[k];
        d32[k] = (float)dsp[k];
        jv32[k] = v32[k] = (float)v[k];
        w32[k] = (float)w[k];
    }
    OK(dk_elasticity_tangent_f32(&cells1, 1, iscr, NT + 1 + 3 * NT, &graph, 2, fix, N, &o32,
                                 NULL, 0, p32, 2 * N, d32, 2 * N, jv32, 2 * N, scratch32, slen,
                                 &r));
    OK(dk_elasticity_adjoint_f32(&cells1, 1, iscr, NT + 1 + 3 * NT, &graph, 2, fix, N, &o32,
                                 NULL, 0, p32, 2 * N, d32, 2 * N, w32, 2 * N, g32, 2 * N,
                                 scratch32, slen, &r));
    CHECK(identity(dotf(jv32, w32), dotf(v32, g32), dotf(jv32, jv32), dotf(w32, w32)) <= 1e-4);

    /* Bad input: the status, and dx and g untouched. */
    memcpy(keep, jv, sizeof keep);
    EXPECT(dk_elasticity_tangent(&cells, 0, NULL, 0, &graph, 2, fix, N, &o, NULL, 0, pts,
                                 2 * N, dsp, 2 * N, jv, 2 * N, scratch, slen - 1, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(dk_elasticity_tangent(&cells, 0, NULL, 0, &graph, 4, fix, N, &o, NULL, 0, pts,
                                 2 * N, dsp, 2 * N, jv, 2 * N, scratch, slen, &r),
           DK_ERR_INVALID_PARAMETER);
    SAME(jv, keep, sizeof keep);
    memcpy(keep, g, sizeof keep);
    o.steps = 0;
    EXPECT(dk_elasticity_adjoint(&cells, 0, NULL, 0, &graph, 2, fix, N, &o, NULL, 0, pts,
                                 2 * N, dsp, 2 * N, w, 2 * N, g, 2 * N, scratch, slen, &r),
           DK_ERR_INVALID_PARAMETER);
    SAME(g, keep, sizeof keep);
    EXPECT(dk_elasticity_sensitivity_scratch_len(N, NT, used, 1, 3, &slen),
           DK_ERR_INVALID_PARAMETER);
    if (failures) return 1;
    printf("elasticity_sensitivity: every check held\n");
    return 0;
}

/* The per-precision part of deformation_fast.c: included once with REAL double (FN(name) =
 * name, SUF f64, HEX hex64, TOL 1e-12) and once with REAL float (FN(name) = name_f32, SUF
 * f32, HEX hex32, TOL 1e-4). */

/* Sets `buf[0..n)` to a bit pattern no call computes. */
static void CAT(fill_, SUF)(REAL *buf, size_t n) { memset(buf, 0x5A, n * sizeof(REAL)); }

/* Whether `buf[0..n)` still holds that pattern. */
static int CAT(untouched_, SUF)(const REAL *buf, size_t n) {
    size_t i;
    const unsigned char *b = (const unsigned char *)buf;
    for (i = 0; i < n * sizeof(REAL); i++)
        if (b[i] != 0x5A) return 0;
    return 1;
}

/* A call that must fail with `status` and leave `buf[0..n)` untouched. */
#define BAD(call, status, buf, n)                                                         \
    do {                                                                                  \
        CAT(fill_, SUF)(buf, n);                                                          \
        EXPECT(call, status);                                                             \
        CHECK(CAT(untouched_, SUF)(buf, n));                                              \
    } while (0)

static REAL CAT(p_, SUF)[2 * N], CAT(def_, SUF)[2 * B], CAT(dir_, SUF)[2 * B],
    CAT(w_, SUF)[2 * N], CAT(scratch_, SUF)[WORK], CAT(tree_, SUF)[WORK],
    CAT(tr_, SUF)[2 * N], CAT(rot_, SUF)[4 * N], CAT(out_, SUF)[2 * N],
    CAT(tan_, SUF)[2 * N], CAT(back_, SUF)[2 * B];
static uint32_t CAT(tidx_, SUF)[WORK];

/* The forward deformation: prints the mesh and the bound; bad input writes nothing. */
static void CAT(forward_, SUF)(const FN(dk_boundary_motion) * m, const size_t *lens) {
    REAL *p = CAT(p_, SUF), *out = CAT(out_, SUF), *sc = CAT(scratch_, SUF);
    REAL *tree = CAT(tree_, SUF), *tr = CAT(tr_, SUF), *rot = CAT(rot_, SUF);
    uint32_t *ti = CAT(tidx_, SUF);
    REAL origin[2], bound[1];
    size_t i;
    OK(FN(dk_deform_idw_fast)(p, 2 * N, 2, m, 3, (REAL)0.5, (REAL)0.1, sc, lens[0], NULL, 0, ti,
                              lens[1], tree, lens[2], tr, 2 * N, rot, 4 * N, out, 2 * N, origin, 2,
                              bound, 1));
    for (i = 0; i < B; i++) SAME(&out[2 * ring[i]], &m->deformed[2 * i], 2 * sizeof(REAL));
    CHECK(bound[0] >= 0 && bound[0] <= (REAL)0.1);
    HEX("out", out, 2 * N);
    HEX("bound", bound, 1);
    BAD(FN(dk_deform_idw_fast)(p, 2 * N, 2, m, 3, (REAL)0.5, (REAL)0.1, sc, lens[0], NULL, 0, ti,
                               lens[1], tree, lens[2], tr, 2 * N, rot, 4 * N, out, 2 * N, origin, 2,
                               bound, 2),
        DK_ERR_LENGTH_MISMATCH, out, 2 * N);
    BAD(FN(dk_deform_idw_fast)(p, 2 * N, 2, m, 3, (REAL)1.5, (REAL)0.1, sc, lens[0], NULL, 0, ti,
                               lens[1], tree, lens[2], tr, 2 * N, rot, 4 * N, out, 2 * N, origin, 2,
                               bound, 1),
        DK_ERR_INVALID_PARAMETER, out, 2 * N);
    CAT(fill_, SUF)(origin, 2);
    CAT(fill_, SUF)(bound, 1);
    BAD(FN(dk_deform_idw_fast)(p, 2 * N, 2, m, 3, (REAL)0.5, (REAL)0.1, sc, lens[0], NULL, 0, ti,
                               lens[1], tree, lens[2] - 1, tr, 2 * N, rot, 4 * N, out, 2 * N,
                               origin, 2, bound, 1),
        DK_ERR_BUFFER_TOO_SMALL, out, 2 * N);
    CHECK(CAT(untouched_, SUF)(origin, 2) && CAT(untouched_, SUF)(bound, 1));
}

/* The derivative (tangent when `adjoint` is 0) of `in` into `res` with `scratch_len`, `dim`,
 * `theta`, `tolerance`, `exponent` and the tree index length as given. */
static dk_status CAT(deriv_, SUF)(int adjoint, const FN(dk_boundary_motion) * m, uint32_t dim,
                                  REAL exponent, REAL theta, REAL tolerance, const REAL *in,
                                  size_t in_len, size_t scratch_len, size_t tidx_len,
                                  const size_t *lens, REAL *res, size_t res_len) {
    REAL *p = CAT(p_, SUF), *sc = CAT(scratch_, SUF), *tree = CAT(tree_, SUF);
    REAL *tr = CAT(tr_, SUF), *rot = CAT(rot_, SUF);
    uint32_t *ti = CAT(tidx_, SUF);
    if (adjoint)
        return FN(dk_deform_idw_fast_adjoint)(p, 2 * N, dim, m, exponent, theta, tolerance, in,
                                              in_len, sc, scratch_len, NULL, 0, ti, tidx_len,
                                              tree, lens[2], tr, 2 * N, rot, 4 * N, res, res_len);
    return FN(dk_deform_idw_fast_tangent)(p, 2 * N, dim, m, exponent, theta, tolerance, in,
                                          in_len, sc, scratch_len, NULL, 0, ti, tidx_len, tree,
                                          lens[2], tr, 2 * N, rot, 4 * N, res, res_len);
}

/* Tangent and adjoint: printed, the dot-product test, bad input that writes nothing. */
static void CAT(derivatives_, SUF)(const FN(dk_boundary_motion) * m, const size_t *lens) {
    REAL *tan = CAT(tan_, SUF), *back = CAT(back_, SUF), *dir = CAT(dir_, SUF);
    REAL *w = CAT(w_, SUF);
    const REAL half = (REAL)0.5, tol = (REAL)0.1, e = 3;
    double jv_w = 0, v_jtw = 0, scale = 0;
    size_t i;
    OK(CAT(deriv_, SUF)(0, m, 2, e, half, tol, dir, 2 * B, lens[3], lens[1], lens, tan, 2 * N));
    OK(CAT(deriv_, SUF)(1, m, 2, e, half, tol, w, 2 * N, lens[3], lens[1], lens, back, 2 * B));
    for (i = 0; i < 2 * N; i++) {
        jv_w += (double)tan[i] * (double)w[i];
        scale += fabs((double)tan[i] * (double)w[i]);
    }
    for (i = 0; i < 2 * B; i++) v_jtw += (double)dir[i] * (double)back[i];
    CHECK(scale > 1 && fabs(jv_w - v_jtw) <= TOL * scale);
    HEX("tangent", tan, 2 * N);
    HEX("adjoint", back, 2 * B);
    BAD(CAT(deriv_, SUF)(0, m, 4, e, half, tol, dir, 2 * B, lens[3], lens[1], lens, tan, 2 * N),
        DK_ERR_INVALID_PARAMETER, tan, 2 * N);
    BAD(CAT(deriv_, SUF)(0, m, 2, e, 1, tol, dir, 2 * B, lens[3], lens[1], lens, tan, 2 * N),
        DK_ERR_INVALID_PARAMETER, tan, 2 * N);
    BAD(CAT(deriv_, SUF)(0, m, 2, e, half, -1, dir, 2 * B, lens[3], lens[1], lens, tan, 2 * N),
        DK_ERR_INVALID_PARAMETER, tan, 2 * N);
    BAD(CAT(deriv_, SUF)(1, m, 2, -1, half, tol, w, 2 * N, lens[3], lens[1], lens, back, 2 * B),
        DK_ERR_INVALID_PARAMETER, back, 2 * B);
    BAD(CAT(deriv_, SUF)(0, m, 2, e, half, tol, dir, 2 * B, lens[3] - 1, lens[1], lens, tan,
                         2 * N),
        DK_ERR_BUFFER_TOO_SMALL, tan, 2 * N);
    BAD(CAT(deriv_, SUF)(1, m, 2, e, half, tol, w, 2 * N, lens[3], lens[1] - 1, lens, back,
                         2 * B),
        DK_ERR_BUFFER_TOO_SMALL, back, 2 * B);
    BAD(CAT(deriv_, SUF)(0, m, 2, e, half, tol, dir, 2 * B - 1, lens[3], lens[1], lens, tan,
                         2 * N),
        DK_ERR_LENGTH_MISMATCH, tan, 2 * N);
    BAD(CAT(deriv_, SUF)(1, m, 2, e, half, tol, NULL, 2 * N, lens[3], lens[1], lens, back, 2 * B),
        DK_ERR_NULL_POINTER, back, 2 * B);
    dir[3] = (REAL)NAN;
    BAD(CAT(deriv_, SUF)(0, m, 2, e, half, tol, dir, 2 * B, lens[3], lens[1], lens, tan, 2 * N),
        DK_ERR_NON_FINITE, tan, 2 * N);
    w[5] = (REAL)INFINITY;
    BAD(CAT(deriv_, SUF)(1, m, 2, e, half, tol, w, 2 * N, lens[3], lens[1], lens, back, 2 * B),
        DK_ERR_NON_FINITE, back, 2 * B);
}

static void CAT(run_, SUF)(void) {
    FN(dk_boundary_motion) m;
    size_t lens[4], i;
    for (i = 0; i < 2 * N; i++) {
        CAT(p_, SUF)[i] = (REAL)P[i];
        CAT(w_, SUF)[i] = (REAL)W[i];
    }
    for (i = 0; i < 2 * B; i++) {
        CAT(def_, SUF)[i] = (REAL)DEF[i];
        CAT(dir_, SUF)[i] = (REAL)DIR[i];
    }
    OK(dk_deform_idw_fast_lens(N, B, 2, lens));
    EXPECT(dk_deform_idw_fast_lens(N, B, 5, lens), DK_ERR_INVALID_PARAMETER);
    for (i = 0; i < 4; i++) CHECK(lens[i] > 0 && lens[i] <= WORK);
    OK(FN(dk_boundary_motion_default)(&m));
    m.nodes = ring;
    m.nodes_len = B;
    m.deformed = CAT(def_, SUF);
    m.deformed_len = 2 * B;
    m.elements.offsets = seg_offsets;
    m.elements.offsets_len = B + 1;
    m.elements.nodes = seg_nodes;
    m.elements.nodes_len = 2 * B;
    m.elements.kinds = seg_kinds;
    m.elements.kinds_len = B;
    m.rotation_source = DK_ROTATIONS_SHAPE;
    CAT(forward_, SUF)(&m, lens);
    CAT(derivatives_, SUF)(&m, lens);
}
#undef BAD

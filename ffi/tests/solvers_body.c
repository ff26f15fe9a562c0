/* Per-precision part of solvers.c: included once with REAL = double, FN(x) = x and once with
 * REAL = float, FN(x) = x##_f32. Not a translation unit of its own. */

/* ------------------------------------------------------------------------------------------ */
/* Taubin                                                                                      */
/* ------------------------------------------------------------------------------------------ */

static void CAT(taubin_params_, SUF)(void) {
    REAL l = 9, m = 9, l0 = 9, m0 = 9;
    OK(FN(dk_taubin_params_paper)(&l, &m));
    CHECK(l == (REAL)0.330 && m == (REAL)-0.334);
    EXPECT(FN(dk_taubin_params_paper)(NULL, &m), DK_ERR_NULL_POINTER);
    OK(FN(dk_taubin_params_from_pass_band)((REAL)0.33, (REAL)0.1, &l, &m));
    CHECK(l == (REAL)0.33 && m < -l);
    CLOSE(1 / l + 1 / m, 0.1, LOOSE);
    l = l0;
    m = m0;
    EXPECT(FN(dk_taubin_params_from_pass_band)((REAL)-1, (REAL)0.1, &l, &m),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_params_from_pass_band)((REAL)0.33, (REAL)4, &l, &m),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_params_from_pass_band)((REAL)NAN, (REAL)0.1, &l, &m),
           DK_ERR_NON_FINITE);
    EXPECT(FN(dk_taubin_params_from_pass_band)((REAL)0.33, (REAL)0.1, &l, NULL),
           DK_ERR_NULL_POINTER);
    CHECK(l == l0 && m == m0);
}

/* A 6 x 3 block of 2D points whose i-lines all have the spacing 1, 1, 1, 3, 3. */
static void CAT(arclength_grid_, SUF)(REAL *p) {
    static const double xs[6] = {0, 1, 2, 3, 6, 9};
    size_t i, j;
    for (j = 0; j < 3; j++)
        for (i = 0; i < 6; i++) {
            p[2 * (i + 6 * j)] = (REAL)xs[i];
            p[2 * (i + 6 * j) + 1] = (REAL)j;
        }
}

static void CAT(taubin_smooth_arclength_, SUF)(void) {
    REAL p[36], p0[36], scratch[64];
    dk_smooth_arclength_options o;
    dk_smooth_report r, r0;
    uint8_t pins[18];
    size_t need = 0, i, j;

    OK(dk_smooth_arclength_options_default(0, &o));
    o.normalised = 1;
    OK(dk_taubin_smooth_arclength_scratch_len(6, 3, 1, &o, 2, &need));
    CHECK(need == 18 + 18 && need <= 64);
    CAT(arclength_grid_, SUF)(p);
    OK(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, need, &r));
    CHECK(r.iterations == 30);
    CHECK(r.stretching_before == 3.0 && r.stretching_before_point == 3);
    CHECK(r.stretching_after < r.stretching_before && r.stretching_after >= 1.0);
    CHECK(r.max_displacement > 0 && r.last_change > 0);
    for (j = 0; j < 3; j++) {
        /* Normalised: both line ends stay put; points only slide along the straight line. */
        CHECK(p[2 * (0 + 6 * j)] == 0 && p[2 * (5 + 6 * j)] == 9);
        for (i = 0; i < 6; i++) {
            CHECK(p[2 * (i + 6 * j) + 1] == (REAL)j);
            if (i > 0) CHECK(p[2 * (i + 6 * j)] > p[2 * (i - 1 + 6 * j)]);
            /* The two boundary lines j = 0 and j = 2 see the same data (the paper's face rule
             * averages only along the face): they agree bit for bit. */
            if (j == 2) CHECK(p[2 * (i + 6 * j)] == p[2 * i]);
        }
    }

    /* Pinned points do not move; dim 3 gives the same x as dim 2 (z = 0). */
    {
        REAL q[54], s3[96];
        CAT(arclength_grid_, SUF)(p);
        for (i = 0; i < 18; i++) {
            q[3 * i] = p[2 * i];
            q[3 * i + 1] = p[2 * i + 1];
            q[3 * i + 2] = 0;
            pins[i] = (uint8_t)(i == 3 + 6 * 1 ? 7 : 0);
        }
        o.pinned = pins;
        o.pinned_len = 18;
        OK(dk_taubin_smooth_arclength_scratch_len(6, 3, 1, &o, 3, &need));
        CHECK(need <= 96);
        OK(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, q, 54, 3, s3, need, &r));
        CHECK(q[3 * 9] == 3 && q[3 * 9 + 1] == 1 && q[3 * 9 + 2] == 0);
        CHECK(q[3 * 3] != 3); /* the same point on the unpinned line 0 moved */
        o.pinned = NULL;
        o.pinned_len = 0;
    }

    /* Bad input: status, and points and report bit-for-bit unchanged. */
    CAT(arclength_grid_, SUF)(p);
    memcpy(p0, p, sizeof p);
    POISON(r);
    r0 = r;
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, NULL, p, 36, 2, scratch, 64, &r),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, NULL, 36, 2, scratch, 64, &r),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, NULL),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, NULL, 64, &r),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 35, 2, scratch, 64, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 34, 2, scratch, 64, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 4, scratch, 64, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 35, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(FN(dk_taubin_smooth_arclength)(0, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_BAD_DIMENSIONS);
    o.direction = 3;
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_INVALID_PARAMETER);
    o.direction = 0;
    o.lambda = 0;
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_INVALID_PARAMETER);
    o.lambda = NAN;
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_NON_FINITE);
    o.lambda = 0.33;
    o.mu = 0.1;
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_INVALID_PARAMETER);
    o.mu = -0.334;
    o.pinned = pins;
    o.pinned_len = 17;
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_LENGTH_MISMATCH);
    o.pinned = NULL;
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_NULL_POINTER);
    o.pinned_len = 0;
    o.use_coarse = 1;
    o.coarse.factor[1] = 0;
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_INVALID_PARAMETER);
    o.coarse.factor[1] = 1;
    o.coarse.prolongation = 2;
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_INVALID_PARAMETER);
    o.coarse.prolongation = DK_PROLONGATION_VALUES;
    o.use_coarse = 0;
    p[7] = (REAL)NAN;
    memcpy(p0, p, sizeof p);
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_NON_FINITE);
    SAME(p, p0, sizeof p);

    /* Line ends (dk_taubin_smooth_arclength_ends), dimensional: line j = 1 is longer (its end
     * at 9.5), so the face i = 5 is rough. Free: that end slides back along its line, the
     * first points and every y stay; fixed (no face): the ends stay. Faces that cannot be
     * free, normalised, and a seam (two ends at one point) are refused, points unchanged. */
    {
        REAL f[36], f0[36];
        CAT(arclength_grid_, SUF)(f);
        f[2 * (5 + 6 * 1)] = (REAL)9.5;
        memcpy(f0, f, sizeof f);
        o.normalised = 0;
        OK(FN(dk_taubin_smooth_arclength_ends)(6, 3, 1, &o, DK_FACE_IMAX, f, 36, 2, scratch,
                                               64, &r));
        CHECK(f[2 * (5 + 6 * 1)] < (REAL)9.5 && f[2 * (5 + 6 * 1)] > (REAL)9);
        for (j = 0; j < 3; j++) {
            CHECK(f[2 * (6 * j)] == 0);
            for (i = 0; i < 6; i++) CHECK(f[2 * (i + 6 * j) + 1] == (REAL)j);
        }
        memcpy(f, f0, sizeof f);
        OK(FN(dk_taubin_smooth_arclength_ends)(6, 3, 1, &o, 0, f, 36, 2, scratch, 64, &r));
        for (j = 0; j < 3; j++) CHECK(f[2 * (5 + 6 * j)] == f0[2 * (5 + 6 * j)]);
        memcpy(f, f0, sizeof f);
        EXPECT(FN(dk_taubin_smooth_arclength_ends)(6, 3, 1, &o, DK_FACE_IMIN, f, 36, 2, scratch,
                                                   64, &r),
               DK_ERR_INVALID_PARAMETER);
        EXPECT(FN(dk_taubin_smooth_arclength_ends)(6, 3, 1, &o, DK_FACE_JMAX, f, 36, 2, scratch,
                                                   64, &r),
               DK_ERR_INVALID_PARAMETER);
        o.normalised = 1;
        EXPECT(FN(dk_taubin_smooth_arclength_ends)(6, 3, 1, &o, DK_FACE_IMAX, f, 36, 2, scratch,
                                                   64, &r),
               DK_ERR_INVALID_PARAMETER);
        o.normalised = 0;
        SAME(f, f0, sizeof f);
        f[2 * (5 + 6 * 1)] = f[2 * 5];
        f[2 * (5 + 6 * 1) + 1] = f[2 * 5 + 1];
        memcpy(f0, f, sizeof f);
        EXPECT(FN(dk_taubin_smooth_arclength_ends)(6, 3, 1, &o, DK_FACE_IMAX, f, 36, 2, scratch,
                                                   64, &r),
               DK_ERR_SHARED_FREE_END);
        SAME(f, f0, sizeof f);
        r = r0; /* the successful calls above wrote it; the checks below compare with r0 */
    }
    CAT(arclength_grid_, SUF)(p);
    memcpy(p0, p, sizeof p);
    /* An unstable λ (1.9, μ = 0) on the dimensional arclength: the fold guard fires after
     * the filter ran, and still nothing is written. */
    o.normalised = 0;
    o.lambda = 1.9;
    o.mu = 0;
    EXPECT(FN(dk_taubin_smooth_arclength)(6, 3, 1, &o, p, 36, 2, scratch, 64, &r),
           DK_ERR_FOLDED_LINE);
    SAME(p, p0, sizeof p);
    SAME(&r, &r0, sizeof r);

    /* The coarse pass runs and keeps a uniform 5 x 3 grid uniform (coarse indices 0, 2, 4
     * are uniform too, so the arclength stays linear everywhere). */
    OK(dk_smooth_arclength_options_default(0, &o));
    o.use_coarse = 1;
    o.coarse.factor[0] = 2;
    o.coarse.factor[1] = 2;
    for (j = 0; j < 3; j++)
        for (i = 0; i < 5; i++) {
            p[2 * (i + 5 * j)] = (REAL)i;
            p[2 * (i + 5 * j) + 1] = (REAL)j;
        }
    OK(dk_taubin_smooth_arclength_scratch_len(5, 3, 1, &o, 2, &need));
    CHECK(need == 30);
    OK(FN(dk_taubin_smooth_arclength)(5, 3, 1, &o, p, 30, 2, scratch, need, &r));
    CHECK(r.iterations == 45);
    for (i = 0; i < 15; i++) CLOSE(p[2 * i], (REAL)(i % 5), LOOSE);
}

/* A linear field on a ni x nj x nk block: a + b i + c j + d k. */
static REAL CAT(linear_, SUF)(size_t i, size_t j, size_t k) {
    return (REAL)(0.5 + 0.25 * (double)i - 0.75 * (double)j + 1.5 * (double)k);
}

static void CAT(taubin_structured_, SUF)(void) {
    enum { NI = 5, NJ = 4, NK = 3, N = NI * NJ * NK };
    REAL f[N], g[N], h[N], f0[N], s[N];
    dk_structured_options so;
    dk_filter_report r, r0;
    dk_block_region reg;
    REAL lambda = 9, mu = 9, change = 9, c0;
    uint8_t pins[N];
    size_t i, j, k, p;

    OK(FN(dk_taubin_params_paper)(&lambda, &mu));
    memset(&so, 0, sizeof so);
    /* A linear field is a fixed point of every stencil (interior, face, edge). */
    for (k = 0; k < NK; k++)
        for (j = 0; j < NJ; j++)
            for (i = 0; i < NI; i++) f[i + NI * (j + NJ * k)] = CAT(linear_, SUF)(i, j, k);
    OK(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, mu, 20, &so, f, N, s, N, &r));
    CHECK(r.iterations == 20 && r.last_change < LOOSE);
    for (k = 0; k < NK; k++)
        for (j = 0; j < NJ; j++)
            for (i = 0; i < NI; i++)
                CLOSE(f[i + NI * (j + NJ * k)], CAT(linear_, SUF)(i, j, k), LOOSE);

    /* A spike in the middle is damped and stays symmetric about i = 2 and about k = 1. */
    for (p = 0; p < N; p++) {
        f[p] = 0;
        pins[p] = 0;
    }
    f[2 + NI * (1 + NJ * 1)] = 1;
    OK(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, mu, 10, &so, f, N, s, N, &r));
    CHECK(f[2 + NI * (1 + NJ * 1)] < (REAL)0.5 && f[2 + NI * (1 + NJ * 1)] > 0);
    CLOSE(f[1 + NI * (1 + NJ * 1)], f[3 + NI * (1 + NJ * 1)], TOL);
    CLOSE(f[2 + NI * (1 + NJ * 0)], f[2 + NI * (1 + NJ * 2)], TOL);
    /* Corners never move, pinned points keep their value. */
    for (p = 0; p < N; p++) f[p] = 0;
    f[2 + NI * (1 + NJ * 1)] = 1;
    f[0] = (REAL)0.125; /* a corner */
    f[4 + NI * (3 + NJ * 2)] = (REAL)0.25; /* the opposite corner, pinned */
    pins[4 + NI * (3 + NJ * 2)] = 1;
    so.pinned = pins;
    so.pinned_len = N;
    OK(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, mu, 10, &so, f, N, s, N, &r));
    CHECK(f[2 + NI * (1 + NJ * 1)] < (REAL)0.5 && f[2 + NI * (1 + NJ * 1)] > 0);
    CHECK(f[0] == (REAL)0.125 && f[4 + NI * (3 + NJ * 2)] == (REAL)0.25);

    /* One iteration of the whole filter is a λ sweep then a μ sweep over the whole block. */
    for (p = 0; p < N; p++) f[p] = g[p] = (REAL)((p * 7919) % 13) / 13;
    OK(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, mu, 1, &so, f, N, s, N, &r));
    reg.lo[0] = reg.lo[1] = reg.lo[2] = 0;
    reg.hi[0] = NI;
    reg.hi[1] = NJ;
    reg.hi[2] = NK;
    OK(FN(dk_taubin_structured_sweep)(NI, NJ, NK, g, N, lambda, &so, &reg, 0, h, N, &change));
    c0 = change;
    /* The same region 1-based and inclusive (Fortran). */
    reg.lo[0] = reg.lo[1] = reg.lo[2] = 1;
    OK(FN(dk_taubin_structured_sweep)(NI, NJ, NK, h, N, mu, &so, &reg, 1, g, N, &change));
    SAME(f, g, sizeof f);
    CHECK((double)(c0 > change ? c0 : change) == r.last_change);

    /* A sub-region writes only inside it. */
    for (p = 0; p < N; p++) h[p] = 12345;
    reg.lo[0] = 1;
    reg.hi[0] = 3;
    reg.lo[1] = 0;
    reg.hi[1] = 1;
    reg.lo[2] = 2;
    reg.hi[2] = 3;
    OK(FN(dk_taubin_structured_sweep)(NI, NJ, NK, g, N, lambda, &so, &reg, 0, h, N, &change));
    for (k = 0; k < NK; k++)
        for (j = 0; j < NJ; j++)
            for (i = 0; i < NI; i++) {
                int inside = i >= 1 && i < 3 && j < 1 && k == 2;
                CHECK(inside ? h[i + NI * (j + NJ * k)] != 12345
                             : h[i + NI * (j + NJ * k)] == 12345);
            }

    /* Bad input. */
    for (p = 0; p < N; p++) f[p] = (REAL)p;
    memcpy(f0, f, sizeof f);
    for (p = 0; p < N; p++) h[p] = 12345;
    memcpy(g, h, sizeof h);
    POISON(r);
    r0 = r;
    change = c0 = 77;
    EXPECT(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, mu, 3, NULL, f, N, s, N, &r),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, mu, 3, &so, f, N - 1, s, N, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, mu, 3, &so, f, N, s, N - 1, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(FN(dk_taubin_smooth_structured)(NI, NJ, NK, -lambda, mu, 3, &so, f, N, s, N, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, -mu, 3, &so, f, N, s, N, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_smooth_structured)(NI, NJ, NK, (REAL)NAN, mu, 3, &so, f, N, s, N, &r),
           DK_ERR_NON_FINITE);
    EXPECT(FN(dk_taubin_smooth_structured)(NI, NJ, 0, lambda, mu, 3, &so, f, N, s, N, &r),
           DK_ERR_BAD_DIMENSIONS);
    EXPECT(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, mu, 3, &so, f, N, s, N, NULL),
           DK_ERR_NULL_POINTER);
    so.pinned_len = N + 1;
    EXPECT(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, mu, 3, &so, f, N, s, N, &r),
           DK_ERR_LENGTH_MISMATCH);
    so.pinned_len = N;
    f[17] = (REAL)INFINITY;
    memcpy(f0, f, sizeof f);
    EXPECT(FN(dk_taubin_smooth_structured)(NI, NJ, NK, lambda, mu, 3, &so, f, N, s, N, &r),
           DK_ERR_NON_FINITE);
    SAME(f, f0, sizeof f);
    SAME(&r, &r0, sizeof r);
    f[17] = 17;
    reg.lo[0] = 0;
    reg.hi[0] = NI + 1;
    EXPECT(FN(dk_taubin_structured_sweep)(NI, NJ, NK, f, N, lambda, &so, &reg, 0, h, N, &change),
           DK_ERR_INDEX_OUT_OF_RANGE);
    reg.lo[0] = 3;
    reg.hi[0] = 2;
    EXPECT(FN(dk_taubin_structured_sweep)(NI, NJ, NK, f, N, lambda, &so, &reg, 0, h, N, &change),
           DK_ERR_INDEX_OUT_OF_RANGE);
    reg.lo[0] = 0; /* index 0 does not exist 1-based */
    reg.hi[0] = 2;
    EXPECT(FN(dk_taubin_structured_sweep)(NI, NJ, NK, f, N, lambda, &so, &reg, 1, h, N, &change),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(FN(dk_taubin_structured_sweep)(NI, NJ, NK, f, N, lambda, &so, &reg, 2, h, N, &change),
           DK_ERR_BAD_INDEX_BASE);
    EXPECT(FN(dk_taubin_structured_sweep)(NI, NJ, NK, f, N, lambda, &so, NULL, 0, h, N, &change),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_structured_sweep)(NI, NJ, NK, f, N, lambda, &so, &reg, 0, h, N - 1,
                                          &change),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_structured_sweep)(NI, NJ, NK, f, N, (REAL)NAN, &so, &reg, 0, h, N,
                                          &change),
           DK_ERR_NON_FINITE);
    EXPECT(FN(dk_taubin_structured_sweep)(NI, NJ, NK, f, N, lambda, &so, &reg, 0, h, N, NULL),
           DK_ERR_NULL_POINTER);
    SAME(h, g, sizeof h);
    CHECK(change == c0);

    /* Coarse-grid variant: linear fields survive restriction, smoothing and prolongation. */
    {
        dk_taubin_coarse c = {{2, 1, 1}, DK_PROLONGATION_VALUES};
        REAL line[9], line0[9], cs[10];
        size_t need = 0;
        OK(dk_taubin_smooth_structured_coarse_scratch_len(9, 1, 1, &c, &need));
        CHECK(need == 10);
        memset(&so, 0, sizeof so);
        for (i = 0; i < 9; i++) line[i] = (REAL)(2.0 + 0.5 * (double)i);
        OK(FN(dk_taubin_smooth_structured_coarse)(9, 1, 1, &c, lambda, mu, 5, &so, line, 9, cs,
                                                  10, &r));
        CHECK(r.iterations == 5);
        for (i = 0; i < 9; i++) CLOSE(line[i], 2.0 + 0.5 * (double)i, LOOSE);
        c.prolongation = DK_PROLONGATION_CORRECTION;
        line[4] = 7; /* a bump: correction keeps it, values would flatten it */
        OK(FN(dk_taubin_smooth_structured_coarse)(9, 1, 1, &c, lambda, mu, 5, &so, line, 9, cs,
                                                  10, &r));
        CHECK(line[0] == 2 && line[8] == 6);
        memcpy(line0, line, sizeof line);
        POISON(r);
        r0 = r;
        c.factor[2] = 0;
        EXPECT(FN(dk_taubin_smooth_structured_coarse)(9, 1, 1, &c, lambda, mu, 5, &so, line, 9,
                                                      cs, 10, &r),
               DK_ERR_INVALID_PARAMETER);
        c.factor[2] = 1;
        c.prolongation = 5;
        EXPECT(FN(dk_taubin_smooth_structured_coarse)(9, 1, 1, &c, lambda, mu, 5, &so, line, 9,
                                                      cs, 10, &r),
               DK_ERR_INVALID_PARAMETER);
        c.prolongation = DK_PROLONGATION_VALUES;
        EXPECT(FN(dk_taubin_smooth_structured_coarse)(9, 1, 1, &c, lambda, mu, 5, &so, line, 9,
                                                      cs, 9, &r),
               DK_ERR_BUFFER_TOO_SMALL);
        EXPECT(FN(dk_taubin_smooth_structured_coarse)(9, 1, 1, NULL, lambda, mu, 5, &so, line,
                                                      9, cs, 10, &r),
               DK_ERR_NULL_POINTER);
        EXPECT(FN(dk_taubin_smooth_structured_coarse)(9, 1, 1, &c, lambda, mu, 5, &so, line, 8,
                                                      cs, 10, &r),
               DK_ERR_LENGTH_MISMATCH);
        SAME(line, line0, sizeof line);
        SAME(&r, &r0, sizeof r);
    }
}

static void CAT(taubin_graph_, SUF)(void) {
    /* Values with 2 components on the chain 0-1-2-3-4 with fixed ends: a linear first
     * component and a constant second one are fixed points. */
    REAL v[10], v0[10], w[10], s[10], wts[8], pts[10], change = 0, c0;
    REAL lambda, mu;
    uint8_t fixed[5] = {1, 0, 0, 0, 1};
    dk_filter_report r, r0;
    size_t i;

    OK(FN(dk_taubin_params_paper)(&lambda, &mu));
    for (i = 0; i < 5; i++) {
        v[2 * i] = (REAL)(3.0 * (double)i);
        v[2 * i + 1] = (REAL)0.5;
        pts[2 * i] = (REAL)(i * i);
        pts[2 * i + 1] = 0;
    }
    OK(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 0, fixed, 5, lambda, mu, 10, 2, v, 10, s,
                                  10, &r));
    CHECK(r.iterations == 10);
    for (i = 0; i < 5; i++) {
        CLOSE(v[2 * i], 3.0 * (double)i, LOOSE);
        CHECK(v[2 * i + 1] == (REAL)0.5);
    }
    /* Inverse-distance weights of nodes at x = 0, 1, 4, 9, 16: edges in CSR order
     * 0→1, 1→0, 1→2, 2→1, 2→3, 3→2, 3→4, 4→3. */
    OK(FN(dk_taubin_inverse_distance_weights)(&chain_graph, pts, 10, 2, wts, 8));
    CHECK(wts[0] == 1 && wts[1] == 1 && wts[2] == (REAL)1 / 3 && wts[3] == (REAL)1 / 3);
    CHECK(wts[4] == (REAL)1 / 5 && wts[6] == (REAL)1 / 7 && wts[7] == (REAL)1 / 7);
    /* With these weights, values equal to the x coordinate are the arclength-linear field:
     * a fixed point again. */
    for (i = 0; i < 5; i++) v[i] = pts[2 * i];
    OK(FN(dk_taubin_smooth_graph)(&chain_graph, wts, 8, fixed, 5, lambda, mu, 10, 1, v, 5, s, 5,
                                  &r));
    for (i = 0; i < 5; i++) CLOSE(v[i], (double)(i * i), LOOSE);

    /* One iteration == a λ sweep then a μ sweep (bit for bit); the sweep's node range is
     * read 1-based with index_base 1. */
    for (i = 0; i < 10; i++) v[i] = w[i] = (REAL)((i * 37) % 11);
    OK(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 0, NULL, 0, lambda, mu, 1, 2, v, 10, s, 10,
                                  &r));
    OK(FN(dk_taubin_graph_sweep)(&chain_graph, NULL, 0, NULL, 0, w, 10, 2, lambda, 0, 5, 0, s,
                                 10, &change));
    c0 = change;
    OK(FN(dk_taubin_graph_sweep)(&chain_graph, NULL, 0, NULL, 0, s, 10, 2, mu, 1, 5, 1, w, 10,
                                 &change));
    SAME(v, w, sizeof v);
    CHECK((double)(c0 > change ? c0 : change) == r.last_change);
    /* A partial range writes only its nodes (1-based 2..3 = nodes 1, 2). */
    for (i = 0; i < 10; i++) s[i] = 12345;
    OK(FN(dk_taubin_graph_sweep)(&chain_graph, NULL, 0, NULL, 0, w, 10, 2, lambda, 2, 3, 1, s,
                                 10, &change));
    for (i = 0; i < 10; i++) CHECK((i >= 2 && i < 6) ? s[i] != 12345 : s[i] == 12345);

    /* Bad input. */
    for (i = 0; i < 10; i++) v[i] = (REAL)i;
    memcpy(v0, v, sizeof v);
    for (i = 0; i < 10; i++) w[i] = 12345;
    POISON(r);
    r0 = r;
    change = c0 = 77;
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 0, NULL, 0, lambda, mu, 1, 2, v, 9, s,
                                      10, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 0, NULL, 0, lambda, mu, 1, 2, v, 8, s,
                                      10, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 0, NULL, 0, lambda, mu, 1, 8, v, 10, s,
                                      10, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 0, NULL, 0, lambda, mu, 1, 2, v, 10, s,
                                      9, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, wts, 7, NULL, 0, lambda, mu, 1, 2, v, 10, s,
                                      10, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 8, NULL, 0, lambda, mu, 1, 2, v, 10, s,
                                      10, &r),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 0, fixed, 4, lambda, mu, 1, 2, v, 10,
                                      s, 10, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_smooth_graph)(GRAPH(chain_off, 5, chain_tgt, 8), NULL, 0, NULL, 0,
                                      lambda, mu, 1, 2, v, 10, s, 10, &r),
           DK_ERR_BAD_OFFSETS);
    {
        uint32_t bad_tgt[8];
        memcpy(bad_tgt, chain_tgt, sizeof bad_tgt);
        bad_tgt[3] = 9;
        EXPECT(FN(dk_taubin_smooth_graph)(GRAPH(chain_off, 6, bad_tgt, 8), NULL, 0, NULL, 0,
                                          lambda, mu, 1, 2, v, 10, s, 10, &r),
               DK_ERR_INDEX_OUT_OF_RANGE);
    }
    wts[3] = -1;
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, wts, 8, NULL, 0, lambda, mu, 1, 2, v, 10, s,
                                      10, &r),
           DK_ERR_NON_POSITIVE);
    wts[3] = (REAL)NAN;
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, wts, 8, NULL, 0, lambda, mu, 1, 2, v, 10, s,
                                      10, &r),
           DK_ERR_NON_FINITE);
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 0, NULL, 0, lambda, mu, 1, 2, v, 10, s,
                                      10, NULL),
           DK_ERR_NULL_POINTER);
    v[3] = (REAL)NAN;
    memcpy(v0, v, sizeof v);
    EXPECT(FN(dk_taubin_smooth_graph)(&chain_graph, NULL, 0, NULL, 0, lambda, mu, 1, 2, v, 10, s,
                                      10, &r),
           DK_ERR_NON_FINITE);
    SAME(v, v0, sizeof v);
    SAME(&r, &r0, sizeof r);
    EXPECT(FN(dk_taubin_graph_sweep)(&chain_graph, NULL, 0, NULL, 0, v, 10, 2, lambda, 0, 5, 0,
                                     w, 10, &change),
           DK_ERR_NON_FINITE);
    v[3] = 3;
    EXPECT(FN(dk_taubin_graph_sweep)(&chain_graph, NULL, 0, NULL, 0, v, 10, 2, lambda, 0, 6, 0,
                                     w, 10, &change),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(FN(dk_taubin_graph_sweep)(&chain_graph, NULL, 0, NULL, 0, v, 10, 2, lambda, 0, 5, 1,
                                     w, 10, &change),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(FN(dk_taubin_graph_sweep)(&chain_graph, NULL, 0, NULL, 0, v, 10, 2, lambda, 0, 5, 2,
                                     w, 10, &change),
           DK_ERR_BAD_INDEX_BASE);
    EXPECT(FN(dk_taubin_graph_sweep)(&chain_graph, NULL, 0, NULL, 0, v, 10, 2, (REAL)NAN, 0, 5,
                                     0, w, 10, &change),
           DK_ERR_NON_FINITE);
    EXPECT(FN(dk_taubin_graph_sweep)(&chain_graph, NULL, 0, NULL, 0, v, 10, 2, lambda, 0, 5, 0,
                                     w, 10, NULL),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_graph_sweep)(&chain_graph, NULL, 0, NULL, 0, v, 10, 2, lambda, 0, 5, 0,
                                     NULL, 10, &change),
           DK_ERR_NULL_POINTER);
    for (i = 0; i < 10; i++) CHECK(w[i] == 12345);
    CHECK(change == c0);
    for (i = 0; i < 8; i++) wts[i] = 12345;
    pts[2] = pts[0]; /* node 1 on node 0: a zero-length edge */
    pts[3] = pts[1];
    EXPECT(FN(dk_taubin_inverse_distance_weights)(&chain_graph, pts, 10, 2, wts, 8),
           DK_ERR_ZERO_LENGTH_EDGE);
    pts[2] = (REAL)NAN;
    EXPECT(FN(dk_taubin_inverse_distance_weights)(&chain_graph, pts, 10, 2, wts, 8),
           DK_ERR_NON_FINITE);
    pts[2] = 1;
    EXPECT(FN(dk_taubin_inverse_distance_weights)(&chain_graph, pts, 10, 2, wts, 7),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_inverse_distance_weights)(&chain_graph, pts, 10, 3, wts, 8),
           DK_ERR_LENGTH_MISMATCH); /* 10 scalars are not whole 3D points */
    EXPECT(FN(dk_taubin_inverse_distance_weights)(&chain_graph, pts, 10, 1, wts, 8),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_inverse_distance_weights)(&chain_graph, NULL, 10, 2, wts, 8),
           DK_ERR_NULL_POINTER);
    for (i = 0; i < 8; i++) CHECK(wts[i] == 12345);
}

static void CAT(taubin_lines_, SUF)(void) {
    /* One i-line of 4 points at x = 0, 1, 3, 6 (2D), as a 4 x 1 x 1 block. */
    REAL p[8] = {0, 0, 1, 0, 3, 0, 6, 0}, p0[8], out[4], s[16], t[4], maxd = 9, v = 9;
    size_t at = 99, need = 0, i;

    OK(FN(dk_taubin_arclength)(4, 1, 1, p, 8, 2, 0, false, out, 4));
    CHECK(out[0] == 0 && out[1] == 1 && out[2] == 3 && out[3] == 6);
    OK(FN(dk_taubin_arclength)(4, 1, 1, p, 8, 2, 0, true, out, 4));
    CHECK(out[0] == 0 && out[1] == (REAL)1 / 6 && out[2] == (REAL)0.5 && out[3] == 1);
    OK(FN(dk_taubin_stretching)(4, 1, 1, p, 8, 2, 0, out, 4));
    CHECK(out[0] == 1 && out[1] == 2 && out[2] == (REAL)1.5 && out[3] == 1);
    OK(FN(dk_taubin_max_stretching)(4, 1, 1, p, 8, 2, 0, &v, &at));
    CHECK(v == 2 && at == 1);

    OK(dk_taubin_redistribute_scratch_len(4, 1, 1, 2, 0, &need));
    CHECK(need == 12);
    /* Targets = the current arclength: nothing moves (exactly). */
    OK(FN(dk_taubin_arclength)(4, 1, 1, p, 8, 2, 0, false, t, 4));
    memcpy(p0, p, sizeof p);
    OK(FN(dk_taubin_redistribute)(4, 1, 1, 0, t, 4, false, p, 8, 2, s, need, &maxd));
    SAME(p, p0, sizeof p);
    CHECK(maxd == 0);
    /* Uniform normalised targets: equal spacing 2. */
    t[0] = 0;
    t[1] = (REAL)1 / 3;
    t[2] = (REAL)2 / 3;
    t[3] = 1;
    OK(FN(dk_taubin_redistribute)(4, 1, 1, 0, t, 4, true, p, 8, 2, s, need, &maxd));
    CLOSE(p[2], 2, TOL);
    CLOSE(p[4], 4, TOL);
    CHECK(p[0] == 0 && p[6] == 6 && p[1] == 0 && p[7] == 0);
    CLOSE(maxd, 1, TOL);

    /* Fold guard. */
    out[0] = 0;
    out[1] = 1;
    out[2] = 2;
    out[3] = 3;
    OK(FN(dk_taubin_check_lines_increasing)(4, 1, 1, out, 4, 0, 1, NULL, 0, 0));
    out[2] = 1;
    EXPECT(FN(dk_taubin_check_lines_increasing)(4, 1, 1, out, 4, 0, 1, NULL, 0, 0),
           DK_ERR_FOLDED_LINE);
    {
        /* A collapsed line (all points equal) is exempt when the points are given. */
        REAL c[12] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
        OK(FN(dk_taubin_check_lines_increasing)(4, 1, 1, out, 4, 0, 1, c, 12, 3));
        EXPECT(FN(dk_taubin_check_lines_increasing)(4, 1, 1, out, 4, 0, 1, c, 12, 4),
               DK_ERR_INVALID_PARAMETER);
        EXPECT(FN(dk_taubin_check_lines_increasing)(4, 1, 1, out, 4, 0, 1, c, 11, 3),
               DK_ERR_LENGTH_MISMATCH);
        c[4] = (REAL)NAN;
        EXPECT(FN(dk_taubin_check_lines_increasing)(4, 1, 1, out, 4, 0, 1, c, 12, 3),
               DK_ERR_NON_FINITE);
    }
    EXPECT(FN(dk_taubin_check_lines_increasing)(4, 1, 1, out, 3, 0, 1, NULL, 0, 0),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_check_lines_increasing)(4, 1, 1, out, 4, 3, 1, NULL, 0, 0),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_check_lines_increasing)(4, 1, 1, NULL, 4, 0, 1, NULL, 0, 0),
           DK_ERR_NULL_POINTER);

    /* Bad input for the line tools: outputs untouched. */
    for (i = 0; i < 4; i++) out[i] = 12345;
    v = 12345;
    at = 12345;
    maxd = 12345;
    p[3] = (REAL)NAN;
    EXPECT(FN(dk_taubin_arclength)(4, 1, 1, p, 8, 2, 0, false, out, 4), DK_ERR_NON_FINITE);
    EXPECT(FN(dk_taubin_stretching)(4, 1, 1, p, 8, 2, 0, out, 4), DK_ERR_NON_FINITE);
    EXPECT(FN(dk_taubin_max_stretching)(4, 1, 1, p, 8, 2, 0, &v, &at), DK_ERR_NON_FINITE);
    p[3] = 0;
    EXPECT(FN(dk_taubin_arclength)(4, 1, 1, p, 8, 2, 3, false, out, 4),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_arclength)(4, 1, 1, p, 8, 2, 0, false, out, 3), DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_arclength)(4, 1, 1, p, 6, 2, 0, false, out, 4), DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_arclength)(4, 1, 1, p, 8, 5, 0, false, out, 4),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_arclength)(4, 1, 1, p, 8, 2, 0, false, NULL, 4), DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_stretching)(4, 2, 1, p, 8, 2, 0, out, 4), DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_stretching)(4, 1, 1, p, 8, 2, 7, out, 4), DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_taubin_max_stretching)(4, 1, 1, p, 8, 2, 0, &v, NULL), DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_max_stretching)(4, 1, 1, p, 8, 2, 0, NULL, &at), DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_max_stretching)(0, 1, 1, p, 8, 2, 0, &v, &at), DK_ERR_BAD_DIMENSIONS);
    for (i = 0; i < 4; i++) CHECK(out[i] == 12345);
    CHECK(v == 12345 && at == 12345);
    memcpy(p0, p, sizeof p);
    t[2] = (REAL)NAN;
    EXPECT(FN(dk_taubin_redistribute)(4, 1, 1, 0, t, 4, true, p, 8, 2, s, 12, &maxd),
           DK_ERR_NON_FINITE);
    t[2] = (REAL)0.5;
    EXPECT(FN(dk_taubin_redistribute)(4, 1, 1, 0, t, 4, true, p, 8, 2, s, 11, &maxd),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(FN(dk_taubin_redistribute)(4, 1, 1, 0, t, 3, true, p, 8, 2, s, 12, &maxd),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_taubin_redistribute)(4, 1, 1, 0, t, 4, true, p, 8, 2, s, 12, NULL),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_taubin_redistribute)(4, 1, 1, 4, t, 4, true, p, 8, 2, s, 12, &maxd),
           DK_ERR_INVALID_PARAMETER);
    SAME(p, p0, sizeof p);
    CHECK(maxd == 12345);
}

/* ------------------------------------------------------------------------------------------ */
/* Springs                                                                                     */
/* ------------------------------------------------------------------------------------------ */

static void CAT(springs_linear_, SUF)(void) {
    REAL pts[10], k[8], kg[48], v[10], v0[10], s[4 * 16 * 2], res = 9;
    REAL gv[GRID_N], gv0[GRID_N], gx[2 * GRID_N];
    uint32_t idx[GRID_N];
    uint8_t fixed[5] = {1, 0, 0, 0, 1}, gfixed[GRID_N];
    /* The chain's and the grid's spring systems; the arrays are filled below. */
    const FN(dk_spring_system) sys = {chain_graph, k, 8, fixed, 5};
    const FN(dk_spring_system) grid_sys = {grid_graph, kg, 48, gfixed, 16};
    dk_spring_solve_options o;
    dk_spring_solve_report r, r0;
    dk_spring_sweep sw, sw0;
    size_t i, j, m, need = 0;
    const uint32_t methods[6][2] = {
        {DK_LINEAR_JACOBI, 0},         {DK_LINEAR_GAUSS_SEIDEL, 0},
        {DK_LINEAR_SOR, 0},            {DK_LINEAR_CG, DK_PRECONDITIONER_NONE},
        {DK_LINEAR_CG, DK_PRECONDITIONER_JACOBI}, {DK_LINEAR_CG, DK_PRECONDITIONER_SSOR}};

    /* Batina stiffness on the chain at x = 0, 1, 3, 6, 10. */
    for (i = 0; i < 5; i++) {
        pts[2 * i] = (REAL)(i * (i + 1) / 2);
        pts[2 * i + 1] = 0;
    }
    OK(FN(dk_spring_batina_stiffness)(&chain_graph, pts, 10, 2, 1, k, 8));
    CHECK(k[0] == 1 && k[1] == 1 && k[2] == (REAL)0.5 && k[3] == (REAL)0.5);
    CHECK(k[4] == (REAL)1 / 3 && k[6] == (REAL)0.25 && k[7] == (REAL)0.25);
    OK(FN(dk_spring_batina_stiffness)(&chain_graph, pts, 10, 2, 2, k, 8));
    CHECK(k[2] == (REAL)0.25 && k[7] == (REAL)1 / 16);

    OK(FN(dk_spring_solve_options_default)(&o));
    CHECK(o.max_iterations == 10000 && o.update_tol == 0 && o.omega == 1);
    CHECK(o.method == DK_LINEAR_CG && o.preconditioner == DK_PRECONDITIONER_JACOBI);
    CHECK(o.residual_tol > 0 && o.residual_tol <= 2e-5);

    /* Chain with the stiffness 1/|d| at x = 0, 1, 3, 6, 10: the solution of the springs is
     * linear in x (equal force k |d| = 1 ... per unit value jump): values = x / 10 for
     * boundary values 0 and 1; component 2 is constant 7. Every method must find it. */
    OK(FN(dk_spring_batina_stiffness)(&chain_graph, pts, 10, 2, 1, k, 8));
    for (m = 0; m < 6; m++) {
        o.method = methods[m][0];
        o.preconditioner = methods[m][1];
        o.omega = (REAL)1.5;
        for (i = 0; i < 5; i++) {
            v[2 * i] = 0;
            v[2 * i + 1] = 7;
        }
        v[8] = 1;
        OK(dk_spring_solve_linear_scratch_len(5, 2, &o, &need));
        CHECK(need <= sizeof s / sizeof s[0]);
        OK(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, need ? s : NULL, need, idx, 5, &r));
        CHECK(r.converged && r.iterations > 0 && r.residual <= o.residual_tol);
        for (i = 0; i < 5; i++) {
            CLOSE(v[2 * i], pts[2 * i] / 10, LOOSE);
            CLOSE(v[2 * i + 1], 7, LOOSE);
        }
        OK(FN(dk_spring_relative_residual)(&sys, 2, v, 10, idx, 5, &res));
        CLOSE(res, r.residual, TOL);
    }

    /* Maximum principle on the 4 x 4 grid (uniform stiffness): boundary values in [−2, 3],
     * interior values strictly inside; symmetric data give a symmetric answer. */
    for (i = 0; i < 48; i++) kg[i] = 1;
    for (j = 0; j < 4; j++)
        for (i = 0; i < 4; i++) {
            size_t n = i + 4 * j;
            int boundary = i == 0 || j == 0 || i == 3 || j == 3;
            gfixed[n] = (uint8_t)boundary;
            gv[n] = boundary ? (REAL)((double)((n * 5) % 6) - 2.0) : 0;
            gx[2 * n] = (REAL)i;
            gx[2 * n + 1] = (REAL)j;
        }
    OK(FN(dk_spring_solve_options_default)(&o));
    o.method = DK_LINEAR_CG;
    o.preconditioner = DK_PRECONDITIONER_SSOR;
    o.omega = 1.2;
    OK(FN(dk_spring_solve_linear)(&grid_sys, &o, 1, gv, 16, s, 80, idx, 16, &r));
    CHECK(r.converged);
    for (i = 0; i < 16; i++)
        if (!gfixed[i]) CHECK(gv[i] > -2 && gv[i] < 3);
    /* Linear boundary data x + 2y reproduce the linear field inside. */
    for (i = 0; i < 16; i++) gv[i] = gfixed[i] ? gx[2 * i] + 2 * gx[2 * i + 1] : 0;
    OK(FN(dk_spring_solve_linear)(&grid_sys, &o, 1, gv, 16, s, 80, idx, 16, &r));
    for (i = 0; i < 16; i++) CLOSE(gv[i], gx[2 * i] + 2 * gx[2 * i + 1], LOOSE);

    /* Relative residual of the zero interior guess is exactly 1 (r = b). */
    for (i = 0; i < 16; i++) gv[i] = gfixed[i] ? (REAL)(i % 3) + 1 : 0;
    OK(FN(dk_spring_relative_residual)(&grid_sys, 1, gv, 16, idx, 16, &res));
    CHECK(res == 1);

    /* Sweeps: a Jacobi sweep sets each free node to the mean of its neighbours in src; the
     * node range is honoured (1-based 2..3 = nodes 1, 2); SOR with ω = 1 is Gauss–Seidel. */
    for (i = 0; i < 8; i++) k[i] = 1;
    for (i = 0; i < 5; i++) v[i] = (REAL)(i * i); /* 0 1 4 9 16 */
    for (i = 0; i < 5; i++) v0[i] = 12345;
    OK(FN(dk_spring_jacobi_sweep)(&sys, 2, 3, 1, 1, v, 5, v0, 5, idx, 5, &sw));
    CHECK(v0[0] == 12345 && v0[1] == 2 && v0[2] == 5 && v0[3] == 12345 && v0[4] == 12345);
    CHECK(sw.max_change == 1 && sw.residual_sq == 8); /* residuals 2 and 2 */
    OK(FN(dk_spring_jacobi_sweep)(&sys, 0, 5, 0, 1, v, 5, v0, 5, idx, 5, &sw));
    CHECK(v0[0] == 0 && v0[1] == 2 && v0[2] == 5 && v0[3] == 10 && v0[4] == 16);
    {
        /* The same sweep in two ranges with exact residual words: their element-wise sum,
         * rounded, is the whole sweep's residual (residuals 2, 2, 2 at nodes 1–3: 12). */
        int64_t w1[DK_EXACT_SUM_WORDS], w2[DK_EXACT_SUM_WORDS];
        double total = -1;
        dk_spring_sweep sw1, sw2;
        int k2;
        OK(FN(dk_spring_jacobi_sweep_exact)(&sys, 0, 2, 0, 1, v, 5, v0, 5, idx, 5, &sw1, w1));
        OK(FN(dk_spring_jacobi_sweep_exact)(&sys, 2, 5, 0, 1, v, 5, v0, 5, idx, 5, &sw2, w2));
        for (k2 = 0; k2 < DK_EXACT_SUM_WORDS; k2++) w1[k2] += w2[k2];
        OK(dk_exact_sum_value(w1, &total));
        CHECK(total == sw.residual_sq && total == 12);
        CHECK(v0[0] == 0 && v0[1] == 2 && v0[2] == 5 && v0[3] == 10 && v0[4] == 16);
        EXPECT(dk_exact_sum_value(NULL, &total), DK_ERR_NULL_POINTER);
    }
    OK(FN(dk_spring_sor_sweep)(&sys, 0, 5, 0, 1, 1, v, 5, idx, 5, &sw));
    /* Gauss–Seidel: v1 = (0 + 4)/2 = 2, v2 = (2 + 9)/2 = 5.5, v3 = (5.5 + 16)/2 = 10.75. */
    CHECK(v[0] == 0 && v[1] == 2 && v[2] == (REAL)5.5 && v[3] == (REAL)10.75 && v[4] == 16);
    CHECK(sw.max_change == (REAL)1.75);

    /* Bad input: values, report and sweep untouched. */
    for (i = 0; i < 10; i++) v[i] = (REAL)i;
    v[0] = 0;
    memcpy(v0, v, sizeof v);
    POISON(r);
    r0 = r;
    POISON(sw);
    sw0 = sw;
    OK(FN(dk_spring_solve_options_default)(&o));
    EXPECT(FN(dk_spring_solve_linear)(&sys, NULL, 2, v, 10, s, 40, idx, 5, &r),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 39, idx, 5, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, idx, 4, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, NULL, 5, &r),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 9, s, 40, idx, 5, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_spring_solve_linear)(SYSTEM(&chain_graph, k, 8, fixed, 4), &o, 2, v, 10, s, 40,
                                      idx, 5, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_spring_solve_linear)(SYSTEM(&chain_graph, k, 7, fixed, 5), &o, 2, v, 10, s, 40,
                                      idx, 5, &r),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 0, v, 10, s, 40, idx, 5, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, idx, 5, NULL),
           DK_ERR_NULL_POINTER);
    {
        uint8_t none[5] = {0, 0, 0, 0, 0};
        EXPECT(FN(dk_spring_solve_linear)(SYSTEM(&chain_graph, k, 8, none, 5), &o, 2, v, 10, s,
                                          40, idx, 5, &r),
               DK_ERR_UNANCHORED);
    }
    k[2] = 2; /* k(1→2) != k(2→1) */
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, idx, 5, &r),
           DK_ERR_NOT_SYMMETRIC);
    k[2] = 1;
    k[5] = k[4] = 0;
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, idx, 5, &r),
           DK_ERR_NON_POSITIVE);
    k[5] = k[4] = (REAL)NAN;
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, idx, 5, &r),
           DK_ERR_NON_FINITE);
    k[5] = k[4] = 1;
    o.method = DK_LINEAR_SOR;
    o.omega = 2;
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, idx, 5, &r),
           DK_ERR_INVALID_PARAMETER);
    o.method = 17;
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, idx, 5, &r),
           DK_ERR_INVALID_PARAMETER);
    o.method = DK_LINEAR_CG;
    o.preconditioner = 17;
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, idx, 5, &r),
           DK_ERR_INVALID_PARAMETER);
    o.preconditioner = DK_PRECONDITIONER_JACOBI;
    o.residual_tol = -1;
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, idx, 5, &r),
           DK_ERR_INVALID_PARAMETER);
    o.residual_tol = 1e-5;
    v[5] = (REAL)NAN;
    memcpy(v0, v, sizeof v);
    EXPECT(FN(dk_spring_solve_linear)(&sys, &o, 2, v, 10, s, 40, idx, 5, &r),
           DK_ERR_NON_FINITE);
    SAME(v, v0, sizeof v);
    SAME(&r, &r0, sizeof r);
    v[5] = 5;
    memcpy(v0, v, sizeof v);
    for (i = 0; i < 5; i++) gv0[i] = gv[i] = 12345;
    EXPECT(FN(dk_spring_jacobi_sweep)(&sys, 0, 6, 0, 1, v, 5, gv, 5, idx, 5, &sw),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(FN(dk_spring_jacobi_sweep)(&sys, 0, 5, 1, 1, v, 5, gv, 5, idx, 5, &sw),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(FN(dk_spring_jacobi_sweep)(&sys, 1, 5, 2, 1, v, 5, gv, 5, idx, 5, &sw),
           DK_ERR_BAD_INDEX_BASE);
    EXPECT(FN(dk_spring_jacobi_sweep)(&sys, 0, 5, 0, 1, v, 5, gv, 4, idx, 5, &sw),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_spring_jacobi_sweep)(&sys, 0, 5, 0, 1, v, 5, gv, 5, idx, 5, NULL),
           DK_ERR_NULL_POINTER);
    SAME(gv, gv0, 5 * sizeof gv[0]);
    EXPECT(FN(dk_spring_sor_sweep)(&sys, 0, 5, 0, 0, 1, v, 5, idx, 5, &sw),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_spring_sor_sweep)(&sys, 0, 9, 0, 1, 1, v, 5, idx, 5, &sw),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(FN(dk_spring_sor_sweep)(&sys, 0, 5, 0, 1, 9, v, 5, idx, 5, &sw),
           DK_ERR_INVALID_PARAMETER);
    v[2] = (REAL)INFINITY;
    memcpy(v0, v, sizeof v);
    EXPECT(FN(dk_spring_sor_sweep)(&sys, 0, 5, 0, 1, 1, v, 5, idx, 5, &sw),
           DK_ERR_NON_FINITE);
    SAME(v, v0, sizeof v);
    SAME(&sw, &sw0, sizeof sw);
    res = 12345;
    EXPECT(FN(dk_spring_relative_residual)(&sys, 1, v, 5, idx, 5, &res),
           DK_ERR_NON_FINITE);
    v[2] = 2;
    EXPECT(FN(dk_spring_relative_residual)(&sys, 1, v, 4, idx, 5, &res),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_spring_relative_residual)(&sys, 1, v, 5, idx, 5, NULL),
           DK_ERR_NULL_POINTER);
    CHECK(res == 12345);
    for (i = 0; i < 8; i++) k[i] = 12345;
    pts[2] = pts[0];
    EXPECT(FN(dk_spring_batina_stiffness)(&chain_graph, pts, 10, 2, 1, k, 8),
           DK_ERR_ZERO_LENGTH_EDGE);
    EXPECT(FN(dk_spring_batina_stiffness)(&chain_graph, pts, 10, 2, -1, k, 8),
           DK_ERR_INVALID_PARAMETER);
    pts[2] = (REAL)NAN;
    EXPECT(FN(dk_spring_batina_stiffness)(&chain_graph, pts, 10, 2, 1, k, 8),
           DK_ERR_NON_FINITE);
    pts[2] = 1;
    EXPECT(FN(dk_spring_batina_stiffness)(&chain_graph, pts, 10, 2, 1, k, 7),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_spring_batina_stiffness)(&chain_graph, pts, 10, 0, 1, k, 8),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_spring_batina_stiffness)(&chain_graph, pts, 10, 2, 1, NULL, 8),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_spring_batina_stiffness)(GRAPH(NULL, 6, chain_tgt, 8), pts, 10, 2, 1, k, 8),
           DK_ERR_NULL_POINTER);
    for (i = 0; i < 8; i++) CHECK(k[i] == 12345);
    (void)gv0;
}

static void CAT(springs_angle_, SUF)(void) {
    /* The fan: corners of the unit square fixed, the centre free. Every corner displaced by
     * (0.25, −0.5): the centre must follow exactly (a rigid translation). */
    REAL pts[10] = {0, 0, 1, 0, 1, 1, 0, 1, (REAL)0.5, (REAL)0.5};
    REAL k[16], v[10], v0[10], w[10], s[4 * FAN_N * 2], amp = 0, amp0;
    uint32_t idx[FAN_N];
    uint8_t fixed[FAN_N] = {1, 1, 1, 1, 0};
    const FN(dk_spring_system) sys = {fan_graph, k, 16, fixed, 5};
    dk_spring_angle_options o;
    dk_spring_solve_report r, r0;
    dk_spring_sweep sw, sw0;
    size_t i, m, need = 0;
    const uint32_t methods[3] = {DK_ANGLE_DIRECT_GAUSS_SEIDEL, DK_ANGLE_DIRECT_JACOBI,
                                 DK_ANGLE_CG};

    OK(FN(dk_spring_batina_stiffness)(&fan_graph, pts, 10, 2, 1, k, 16));
    OK(FN(dk_spring_angle_options_default)(&o));
    CHECK(o.epsilon == 0.01 && o.method == DK_ANGLE_DIRECT_GAUSS_SEIDEL);
    CHECK(o.max_iterations == 10000 && o.residual_tol > 0 && o.residual_tol <= 2e-5);
    for (m = 0; m < 6; m++) {
        o.method = methods[m % 3];
        o.epsilon = m < 3 ? 0.01 : 0; /* ε = 0 runs the rigidity probe first */
        OK(FN(dk_spring_solve_angle_scratch_len)(FAN_N, 2, &o, &need));
        CHECK(need == (m < 3 ? (size_t[]){0, 10, 40}[m] : 40));
        for (i = 0; i < 4; i++) {
            v[2 * i] = (REAL)0.25;
            v[2 * i + 1] = (REAL)-0.5;
        }
        v[8] = v[9] = 0;
        OK(FN(dk_spring_solve_angle)(&sys, pts, 10, 2, &o, v, 10, need ? s : NULL, need, idx, 5,
                                     &r));
        CHECK(r.converged);
        CLOSE(v[8], 0.25, LOOSE);
        CLOSE(v[9], -0.5, LOOSE);
    }
    /* With one free node whose neighbours are all fixed, one direct sweep is exact. */
    for (i = 0; i < 4; i++) {
        v[2 * i] = (REAL)0.25;
        v[2 * i + 1] = (REAL)-0.5;
    }
    v[8] = v[9] = 0;
    for (i = 0; i < 10; i++) w[i] = 12345;
    OK(FN(dk_spring_angle_jacobi_sweep)(&sys, pts, 10, 2, (REAL)0.01, 5, 5, 1, v, 10, w, 10, idx,
                                        5, &sw));
    CLOSE(w[8], 0.25, TOL);
    CLOSE(w[9], -0.5, TOL);
    for (i = 0; i < 8; i++) CHECK(w[i] == 12345); /* the range was node 5 (1-based) only */
    CLOSE(sw.max_change, 0.5, TOL);
    OK(FN(dk_spring_angle_gauss_seidel_sweep)(&sys, pts, 10, 2, 0, 0, 5, 0, v, 10, idx, 5, &sw));
    CLOSE(v[8], 0.25, TOL);
    CLOSE(v[9], -0.5, TOL);
    OK(dk_spring_angle_rigidity_probe_scratch_len(FAN_N, 2, &need));
    CHECK(need == 40);
    o.epsilon = 0;
    OK(FN(dk_spring_angle_rigidity_probe)(&sys, pts, 10, 2, &o, s, need, idx, 5, &amp));
    CHECK(amp > 0 && amp < 1e3);

    /* Bad input. A collinear neighbourhood makes the free node's block singular. */
    for (i = 0; i < 10; i++) v[i] = (REAL)i / 10;
    memcpy(v0, v, sizeof v);
    for (i = 0; i < 10; i++) w[i] = 12345;
    POISON(r);
    r0 = r;
    POISON(sw);
    sw0 = sw;
    amp0 = amp = 12345;
    OK(FN(dk_spring_angle_options_default)(&o));
    o.epsilon = 0;
    {
        /* Chain along x with the middle node free, ε = 0: its block is singular. */
        REAL cp[10] = {0, 0, 1, 0, 2, 0, 3, 0, 4, 0}, ck[8];
        uint8_t cf[5] = {1, 1, 0, 1, 1};
        const FN(dk_spring_system) chain_sys = {chain_graph, ck, 8, cf, 5};
        for (i = 0; i < 8; i++) ck[i] = 1;
        EXPECT(FN(dk_spring_solve_angle)(&chain_sys, cp, 10, 2, &o, v, 10, s, 40, idx, 5, &r),
               DK_ERR_SINGULAR_NODE);
        EXPECT(FN(dk_spring_angle_rigidity_probe)(&chain_sys, cp, 10, 2, &o, s, 40, idx, 5, &amp),
               DK_ERR_SINGULAR_NODE);
        EXPECT(FN(dk_spring_angle_gauss_seidel_sweep)(&chain_sys, cp, 10, 2, 0, 0, 5, 0, v, 10,
                                                      idx, 5, &sw),
               DK_ERR_SINGULAR_NODE);
    }
    o.epsilon = 0.01;
    EXPECT(FN(dk_spring_solve_angle)(&sys, pts, 10, 3, &o, v, 10, s, 40, idx, 5, &r),
           DK_ERR_LENGTH_MISMATCH); /* 10 scalars are not whole 3D points */
    EXPECT(FN(dk_spring_solve_angle)(&sys, pts, 10, 1, &o, v, 10, s, 40, idx, 5, &r),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_spring_solve_angle)(&sys, pts, 8, 2, &o, v, 10, s, 40, idx, 5, &r),
           DK_ERR_LENGTH_MISMATCH);
    o.method = DK_ANGLE_CG;
    EXPECT(FN(dk_spring_solve_angle)(&sys, pts, 10, 2, &o, v, 10, s, 39, idx, 5, &r),
           DK_ERR_BUFFER_TOO_SMALL);
    o.method = 3;
    EXPECT(FN(dk_spring_solve_angle)(&sys, pts, 10, 2, &o, v, 10, s, 40, idx, 5, &r),
           DK_ERR_INVALID_PARAMETER);
    o.method = DK_ANGLE_DIRECT_GAUSS_SEIDEL;
    o.epsilon = -1;
    EXPECT(FN(dk_spring_solve_angle)(&sys, pts, 10, 2, &o, v, 10, s, 40, idx, 5, &r),
           DK_ERR_INVALID_PARAMETER);
    o.epsilon = 0.01;
    EXPECT(FN(dk_spring_solve_angle)(&sys, pts, 10, 2, NULL, v, 10, s, 40, idx, 5, &r),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_spring_solve_angle)(&sys, pts, 10, 2, &o, v, 10, s, 40, idx, 5, NULL),
           DK_ERR_NULL_POINTER);
    pts[3] = (REAL)NAN;
    EXPECT(FN(dk_spring_solve_angle)(&sys, pts, 10, 2, &o, v, 10, s, 40, idx, 5, &r),
           DK_ERR_NON_FINITE);
    pts[3] = 0;
    v[9] = (REAL)NAN;
    memcpy(v0, v, sizeof v);
    EXPECT(FN(dk_spring_solve_angle)(&sys, pts, 10, 2, &o, v, 10, s, 40, idx, 5, &r),
           DK_ERR_NON_FINITE);
    EXPECT(FN(dk_spring_angle_gauss_seidel_sweep)(&sys, pts, 10, 2, (REAL)0.01, 0, 5, 0, v, 10,
                                                  idx, 5, &sw),
           DK_ERR_NON_FINITE);
    SAME(v, v0, sizeof v);
    SAME(&r, &r0, sizeof r);
    v[9] = 0;
    EXPECT(FN(dk_spring_angle_jacobi_sweep)(&sys, pts, 10, 2, (REAL)0.01, 0, 6, 0, v, 10, w, 10,
                                            idx, 5, &sw),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(FN(dk_spring_angle_jacobi_sweep)(&sys, pts, 10, 2, (REAL)0.01, 0, 5, 2, v, 10, w, 10,
                                            idx, 5, &sw),
           DK_ERR_BAD_INDEX_BASE);
    EXPECT(FN(dk_spring_angle_jacobi_sweep)(&sys, pts, 10, 2, (REAL)NAN, 0, 5, 0, v, 10, w, 10,
                                            idx, 5, &sw),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_spring_angle_jacobi_sweep)(&sys, pts, 10, 2, (REAL)0.01, 0, 5, 0, v, 10, w, 9,
                                            idx, 5, &sw),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_spring_angle_jacobi_sweep)(&sys, pts, 10, 2, (REAL)0.01, 0, 5, 0, v, 10, w, 10,
                                            idx, 5, NULL),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_spring_angle_gauss_seidel_sweep)(&sys, pts, 10, 2, (REAL)0.01, 1, 5, 1, v, 10,
                                                  idx, 4, &sw),
           DK_ERR_BUFFER_TOO_SMALL);
    for (i = 0; i < 10; i++) CHECK(w[i] == 12345);
    SAME(&sw, &sw0, sizeof sw);
    EXPECT(FN(dk_spring_angle_rigidity_probe)(&sys, pts, 10, 2, &o, s, 39, idx, 5, &amp),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(FN(dk_spring_angle_rigidity_probe)(&sys, pts, 10, 2, &o, s, 40, idx, 5, NULL),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_spring_angle_rigidity_probe)(&sys, pts, 10, 2, NULL, s, 40, idx, 5, &amp),
           DK_ERR_NULL_POINTER);
    CHECK(amp == amp0);
    need = 777;
    o.method = 9;
    EXPECT(FN(dk_spring_solve_angle_scratch_len)(FAN_N, 2, &o, &need), DK_ERR_INVALID_PARAMETER);
    o.method = DK_ANGLE_CG;
    EXPECT(FN(dk_spring_solve_angle_scratch_len)(FAN_N, 4, &o, &need), DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_spring_solve_angle_scratch_len)(FAN_N, 2, NULL, &need), DK_ERR_NULL_POINTER);
    CHECK(need == 777);
}

/* ------------------------------------------------------------------------------------------ */
/* Quality                                                                                     */
/* ------------------------------------------------------------------------------------------ */

static void CAT(quality_, SUF)(void) {
    /* Two counter-clockwise triangles; the deformation pushes node 2 through edge 0-1. */
    const uint32_t co[3] = {0, 3, 6}, cn[6] = {0, 1, 2, 0, 2, 3};
    const uint32_t co1[3] = {1, 4, 7}, cn1[6] = {1, 2, 3, 1, 3, 4}; /* the same, 1-based */
    const uint32_t cn_bad[6] = {0, 1, 2, 0, 2, 99};
    const uint8_t ck[2] = {5, 5}, ck_bad[2] = {5, 42}, ck_3d[2] = {5, 10};
    const dk_cells tris = {co, 3, cn, 6, ck, 2}, tris1 = {co1, 3, cn1, 6, ck, 2};
    REAL before[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    REAL after[8] = {0, 0, 1, 0, (REAL)0.5, (REAL)-0.5, 0, 1};
    REAL out[2], out0[2], s[4 * 9];
    size_t count = 99, count0;
    dk_cell_quality q, q0;
    dk_quality_report r, r0;
    dk_wall_angle_change wa, wa0;
    size_t i;

    {
        const REAL square[8] = {0, 0, 1, 0, 1, 1, 0, 1};
        const REAL cube[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                               0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
        const REAL tet[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
        OK(FN(dk_quality_cell_quality)(9, square, 8, 2, &q));
        CHECK(q.measure == 1 && q.min_jacobian == 1 && q.min_scaled_jacobian == 1);
        OK(FN(dk_quality_cell_quality)(5, square, 6, 2, &q));
        CHECK(q.measure == 0.5 && q.min_jacobian == 1);
        CLOSE(q.min_scaled_jacobian, sqrt(0.5), TOL);
        OK(FN(dk_quality_cell_quality)(12, cube, 24, 3, &q));
        CLOSE(q.measure, 1, TOL);
        CHECK(q.min_jacobian == 1 && q.min_scaled_jacobian == 1);
        OK(FN(dk_quality_cell_quality)(10, tet, 12, 3, &q));
        CLOSE(q.measure, 1.0 / 6.0, TOL);
        POISON(q);
        q0 = q;
        EXPECT(FN(dk_quality_cell_quality)(42, square, 8, 2, &q), DK_ERR_UNKNOWN_CELL_KIND);
        EXPECT(FN(dk_quality_cell_quality)(12, square, 8, 2, &q), DK_ERR_CELL_DIMENSION);
        EXPECT(FN(dk_quality_cell_quality)(9, square, 6, 2, &q), DK_ERR_LENGTH_MISMATCH);
        EXPECT(FN(dk_quality_cell_quality)(9, square, 8, 4, &q), DK_ERR_INVALID_PARAMETER);
        EXPECT(FN(dk_quality_cell_quality)(9, NULL, 8, 2, &q), DK_ERR_NULL_POINTER);
        EXPECT(FN(dk_quality_cell_quality)(9, square, 8, 2, NULL), DK_ERR_NULL_POINTER);
        EXPECT(FN(dk_quality_cell_quality)(9, before, 7, 2, &q), DK_ERR_LENGTH_MISMATCH);
        {
            REAL nan_square[8] = {0, 0, 1, 0, 1, 1, 0, 1};
            nan_square[5] = (REAL)NAN;
            EXPECT(FN(dk_quality_cell_quality)(9, nan_square, 8, 2, &q), DK_ERR_NON_FINITE);
        }
        SAME(&q, &q0, sizeof q);
    }

    OK(FN(dk_quality_cell_measures)(&tris, 0, NULL, 0, before, 8, 2, out, 2));
    CHECK(out[0] == 0.5 && out[1] == 0.5);
    OK(FN(dk_quality_cell_measures)(&tris1, 1, iscr, ISCR_LEN, after, 8, 2, out, 2));
    CHECK(out[0] == (REAL)-0.25 && out[1] == (REAL)0.25);
    OK(FN(dk_quality_min_corner_jacobians)(&tris, 0, NULL, 0, before, 8, 2, false, out, 2));
    CHECK(out[0] == 1 && out[1] == 1);
    OK(FN(dk_quality_min_corner_jacobians)(&tris, 0, NULL, 0, before, 8, 2, true, out, 2));
    CLOSE(out[0], sqrt(0.5), TOL);
    OK(FN(dk_quality_inverted_cells)(&tris, 0, NULL, 0, before, 8, after, 8, 2, &count));
    CHECK(count == 1);
    OK(FN(dk_quality_folded_cells)(&tris1, 1, iscr, ISCR_LEN, after, 8, 2, &count));
    CHECK(count == 1);
    OK(FN(dk_quality_folded_cells)(&tris, 0, NULL, 0, before, 8, 2, &count));
    CHECK(count == 0);
    /* No wall: empty wall cells and graph (every array NULL, length 0). */
    OK(FN(dk_quality_compare)(&tris, 0, NULL, 0, &(dk_cells){0}, &(dk_graph){0}, before, 8,
                              after, 8, 2, NULL, 0, &r));
    CHECK(r.cells == 2 && r.inverted_cells == 1 && r.folded_cells == 1);
    CHECK(r.folded_cells_undeformed == 0 && r.degenerate_cells == 0);
    CHECK(r.min_measure_ratio == -0.5 && r.max_measure_ratio == 0.5);
    CHECK(r.min_ratio_cell == 0 && r.max_ratio_cell == 1);
    CHECK(r.min_measure == -0.25 && !r.has_wall && r.wall_node == DK_NO_INDEX);
    OK(FN(dk_quality_compare)(&tris1, 1, iscr, ISCR_LEN, &(dk_cells){0}, &(dk_graph){0}, before,
                              8, after, 8, 2, NULL, 0, &r));
    CHECK(r.min_ratio_cell == 1 && r.max_ratio_cell == 2); /* reported 1-based */

    /* Wall-angle change: a 2 x 2 quad mesh sheared by x += 0.1 y. The wall is the bottom row
     * (lines 0→1, 1→2; normal pointing down, out of the domain); every wall node's first grid
     * line turns by atan(0.1). */
    {
        REAL u[18], d[18];
        const uint32_t wo[3] = {0, 2, 4}, wn[4] = {0, 1, 1, 2};
        const uint32_t wo1[3] = {1, 3, 5}, wn1[4] = {1, 2, 2, 3};
        const uint8_t wk[2] = {3, 3};
        const uint32_t qo[5] = {0, 4, 8, 12, 16};
        const uint32_t qn[16] = {0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7};
        const uint8_t qk[4] = {9, 9, 9, 9};
        const dk_cells segs = {wo, 3, wn, 4, wk, 2}, segs1 = {wo1, 3, wn1, 4, wk, 2};
        const dk_cells quads = {qo, 5, qn, 16, qk, 4};
        size_t j;
        for (j = 0; j < 3; j++)
            for (i = 0; i < 3; i++) {
                u[2 * (i + 3 * j)] = (REAL)i;
                u[2 * (i + 3 * j) + 1] = (REAL)j;
                d[2 * (i + 3 * j)] = (REAL)((double)i + 0.1 * (double)j);
                d[2 * (i + 3 * j) + 1] = (REAL)j;
            }
        OK(dk_quality_wall_angle_scratch_len(9, 2, &count));
        CHECK(count == 36);
        OK(FN(dk_quality_wall_angle_change)(&segs, 0, NULL, 0, &q9_graph, u, 18, d, 18, 2, s, 36,
                                            &wa));
        CLOSE(wa.max_change, atan(0.1), LOOSE);
        CHECK(wa.measured == 3 && wa.skipped == 0 && wa.node < 3);
        OK(FN(dk_quality_wall_angle_change)(&segs1, 1, iscr, ISCR_LEN, &q9_graph, u, 18, d, 18,
                                            2, s, 36, &wa));
        CHECK(wa.node >= 1 && wa.node <= 3); /* 1-based */
        OK(FN(dk_quality_compare)(&quads, 0, NULL, 0, &segs, &q9_graph, u, 18, d, 18, 2, s, 36,
                                  &r));
        CHECK(r.has_wall && r.wall_measured == 3 && r.wall_node < 3);
        CLOSE(r.wall_max_change, atan(0.1), LOOSE);
        CHECK(r.inverted_cells == 0 && r.folded_cells == 0);
        CLOSE(r.min_measure_ratio, 1, TOL); /* a shear keeps areas */

        /* Bad wall input: nothing written. */
        POISON(wa);
        wa0 = wa;
        POISON(r);
        r0 = r;
        EXPECT(FN(dk_quality_wall_angle_change)(&segs, 0, NULL, 0, &q9_graph, u, 18, d, 18, 2, s,
                                                35, &wa),
               DK_ERR_BUFFER_TOO_SMALL);
        EXPECT(FN(dk_quality_wall_angle_change)(&segs, 2, iscr, ISCR_LEN, &q9_graph, u, 18, d,
                                                18, 2, s, 36, &wa),
               DK_ERR_BAD_INDEX_BASE);
        EXPECT(FN(dk_quality_wall_angle_change)(CELLS(wo, 3, wn, 4, qk, 2), 0, NULL, 0,
                                                &q9_graph, u, 18, d, 18, 2, s, 36, &wa),
               DK_ERR_WRONG_NODE_COUNT);
        EXPECT(FN(dk_quality_wall_angle_change)(&segs, 0, NULL, 0, GRAPH(q9_off, 9, q9_tgt, 24),
                                                u, 18, d, 18, 2, s, 36, &wa),
               DK_ERR_BAD_OFFSETS);
        EXPECT(FN(dk_quality_wall_angle_change)(&segs, 0, NULL, 0, &chain_graph, u, 18, d, 18, 2,
                                                s, 36, &wa),
               DK_ERR_LENGTH_MISMATCH); /* a 5-node graph for a 9-node mesh */
        EXPECT(FN(dk_quality_wall_angle_change)(&segs, 0, NULL, 0, &q9_graph, u, 18, d, 16, 2, s,
                                                36, &wa),
               DK_ERR_LENGTH_MISMATCH);
        EXPECT(FN(dk_quality_wall_angle_change)(&segs, 0, NULL, 0, &q9_graph, u, 18, d, 18, 2, s,
                                                36, NULL),
               DK_ERR_NULL_POINTER);
        EXPECT(FN(dk_quality_wall_angle_change)(&segs, 0, NULL, 0, &q9_graph, u, 18, d, 18, 3, s,
                                                36, &wa),
               DK_ERR_LENGTH_MISMATCH);
        d[5] = (REAL)NAN;
        EXPECT(FN(dk_quality_wall_angle_change)(&segs, 0, NULL, 0, &q9_graph, u, 18, d, 18, 2, s,
                                                36, &wa),
               DK_ERR_NON_FINITE);
        EXPECT(FN(dk_quality_compare)(&quads, 0, NULL, 0, &segs, &q9_graph, u, 18, d, 18, 2, s,
                                      36, &r),
               DK_ERR_NON_FINITE);
        d[5] = 0;
        EXPECT(FN(dk_quality_compare)(&quads, 0, NULL, 0, &segs, &q9_graph, u, 18, d, 18, 2, s,
                                      35, &r),
               DK_ERR_BUFFER_TOO_SMALL);
        EXPECT(FN(dk_quality_compare)(&quads, 0, NULL, 0, &segs, GRAPH(NULL, 10, q9_tgt, 24), u,
                                      18, d, 18, 2, s, 36, &r),
               DK_ERR_NULL_POINTER);
        SAME(&wa, &wa0, sizeof wa);
        SAME(&r, &r0, sizeof r);
    }

    /* Bad cell input: outputs untouched. */
    out0[0] = out[0] = 12345;
    out0[1] = out[1] = 12345;
    count0 = count = 12345;
    POISON(r);
    r0 = r;
    EXPECT(FN(dk_quality_cell_measures)(CELLS(co, 3, cn_bad, 6, ck, 2), 0, NULL, 0, before, 8, 2,
                                        out, 2),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(FN(dk_quality_cell_measures)(CELLS(co, 3, cn, 6, ck_bad, 2), 0, NULL, 0, before, 8, 2,
                                        out, 2),
           DK_ERR_UNKNOWN_CELL_KIND);
    EXPECT(FN(dk_quality_cell_measures)(CELLS(co, 3, cn, 6, ck_3d, 2), 0, NULL, 0, before, 8, 2,
                                        out, 2),
           DK_ERR_WRONG_NODE_COUNT);
    EXPECT(FN(dk_quality_cell_measures)(&tris, 2, iscr, ISCR_LEN, before, 8, 2, out, 2),
           DK_ERR_BAD_INDEX_BASE);
    EXPECT(FN(dk_quality_cell_measures)(CELLS(co1, 3, cn, 6, ck, 2), 1, iscr, ISCR_LEN, before,
                                        8, 2, out, 2),
           DK_ERR_INDEX_OUT_OF_RANGE); /* 0-based nodes read 1-based */
    EXPECT(FN(dk_quality_cell_measures)(CELLS(co, 3, cn1, 6, ck, 2), 1, iscr, ISCR_LEN, before,
                                        8, 2, out, 2),
           DK_ERR_BAD_OFFSETS); /* 0-based offsets read 1-based */
    EXPECT(FN(dk_quality_cell_measures)(&tris1, 1, iscr, 8, after, 8, 2, out, 2),
           DK_ERR_BUFFER_TOO_SMALL); /* 1-based needs 3 + 6 index_scratch entries */
    EXPECT(FN(dk_quality_cell_measures)(&tris1, 1, NULL, 0, after, 8, 2, out, 2),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(FN(dk_quality_cell_measures)(&tris, 0, NULL, 0, before, 8, 2, out, 1),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_quality_cell_measures)(&tris, 0, NULL, 0, before, 8, 3, out, 2),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_quality_cell_measures)(&tris, 0, NULL, 0, before, 6, 2, out, 2),
           DK_ERR_INDEX_OUT_OF_RANGE); /* 3 points: node 3 does not exist */
    EXPECT(FN(dk_quality_cell_measures)(CELLS(co, 3, NULL, 6, ck, 2), 0, NULL, 0, before, 8, 2,
                                        out, 2),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_quality_cell_measures)(&tris, 0, NULL, 0, before, 8, 2, NULL, 2),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_quality_min_corner_jacobians)(&tris, 0, NULL, 0, before, 8, 3, true, out, 2),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_quality_min_corner_jacobians)(&tris, 2, iscr, ISCR_LEN, before, 8, 2, true, out,
                                               2),
           DK_ERR_BAD_INDEX_BASE);
    EXPECT(FN(dk_quality_inverted_cells)(&tris, 0, NULL, 0, before, 8, after, 6, 2, &count),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_quality_inverted_cells)(CELLS(co, 3, cn_bad, 6, ck, 2), 0, NULL, 0, before, 8,
                                         after, 8, 2, &count),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(FN(dk_quality_inverted_cells)(&tris, 0, NULL, 0, before, 8, after, 8, 2, NULL),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_quality_folded_cells)(&tris, 7, iscr, ISCR_LEN, before, 8, 2, &count),
           DK_ERR_BAD_INDEX_BASE);
    EXPECT(FN(dk_quality_folded_cells)(CELLS(co, 2, cn, 6, ck, 2), 0, NULL, 0, before, 8, 2,
                                       &count),
           DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_quality_compare)(&tris, 0, NULL, 0, &(dk_cells){0}, &(dk_graph){0}, before, 8,
                                  after, 8, 2, NULL, 0, NULL),
           DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_quality_compare)(CELLS(co, 3, cn_bad, 6, ck, 2), 0, NULL, 0, &(dk_cells){0},
                                  &(dk_graph){0}, before, 8, after, 8, 2, NULL, 0, &r),
           DK_ERR_INDEX_OUT_OF_RANGE);
    after[3] = (REAL)NAN;
    EXPECT(FN(dk_quality_inverted_cells)(&tris, 0, NULL, 0, before, 8, after, 8, 2, &count),
           DK_ERR_NON_FINITE);
    EXPECT(FN(dk_quality_folded_cells)(&tris, 0, NULL, 0, after, 8, 2, &count),
           DK_ERR_NON_FINITE);
    EXPECT(FN(dk_quality_cell_measures)(&tris, 0, NULL, 0, after, 8, 2, out, 2),
           DK_ERR_NON_FINITE);
    EXPECT(FN(dk_quality_min_corner_jacobians)(&tris, 0, NULL, 0, after, 8, 2, false, out, 2),
           DK_ERR_NON_FINITE);
    EXPECT(FN(dk_quality_compare)(&tris, 0, NULL, 0, &(dk_cells){0}, &(dk_graph){0}, before, 8,
                                  after, 8, 2, NULL, 0, &r),
           DK_ERR_NON_FINITE);
    SAME(out, out0, sizeof out);
    CHECK(count == count0);
    SAME(&r, &r0, sizeof r);
}

/* Stiffness choices: wall distances and dual volumes with their factors, scaled springs. */
static void CAT(stiffening_, SUF)(void) {
    REAL pts[10], d[5], d0[5], k[8], k0[8], v[4], cs[2];
    const uint32_t wall0[1] = {0}, wall1[1] = {1}, far[1] = {5};
    const uint32_t co[3] = {0, 3, 6}, cn[6] = {0, 1, 2, 0, 2, 3};
    const uint32_t co1[3] = {1, 4, 7}, cn1[6] = {1, 2, 3, 1, 3, 4};
    const uint8_t ck[2] = {5, 5};
    const dk_cells tris = {co, 3, cn, 6, ck, 2}, tris1 = {co1, 3, cn1, 6, ck, 2};
    const REAL square[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    const REAL f_wall[5] = {1000, 4, (REAL)4 / 3, (REAL)2 / 3, (REAL)0.4};
    size_t i;

    /* The chain at x = 0, 1, 3, 6, 10; the wall is node 0. */
    for (i = 0; i < 5; i++) {
        pts[2 * i] = (REAL)(i * (i + 1) / 2);
        pts[2 * i + 1] = 0;
    }
    OK(FN(dk_spring_wall_distances)(pts, 10, 2, wall0, 1, 0, NULL, 0, d, 5));
    for (i = 0; i < 5; i++) CHECK(d[i] == pts[2 * i]);
    OK(FN(dk_spring_wall_distances)(pts, 10, 2, wall1, 1, 1, iscr, ISCR_LEN, d0, 5));
    SAME(d, d0, sizeof d);
    EXPECT(FN(dk_spring_wall_distances)(pts, 10, 2, far, 1, 0, NULL, 0, d0, 5),
           DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(FN(dk_spring_wall_distances)(pts, 10, 2, wall0, 0, 0, NULL, 0, d0, 5),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_spring_wall_distances)(pts, 10, 2, wall1, 1, 1, NULL, 0, d0, 5),
           DK_ERR_BUFFER_TOO_SMALL);
    SAME(d, d0, sizeof d);
    /* Factors mean / max(d, 1e-3 mean), mean 4: the wall node is floored at 4e-3. */
    OK(FN(dk_spring_wall_distance_factors)(d, 5, 1));
    for (i = 0; i < 5; i++) CLOSE(d[i], f_wall[i], 1e-6 * f_wall[i]);
    memcpy(d0, d, sizeof d);
    EXPECT(FN(dk_spring_wall_distance_factors)(d, 5, -1), DK_ERR_INVALID_PARAMETER);
    SAME(d, d0, sizeof d);
    /* Scaled Batina springs: k_ij (f_i + f_j) / 2, still exactly symmetric. */
    OK(FN(dk_spring_batina_stiffness)(&chain_graph, pts, 10, 2, 1, k, 8));
    memcpy(k0, k, sizeof k);
    OK(FN(dk_spring_scale_stiffness)(&chain_graph, d, 5, k, 8));
    CLOSE(k[0], k0[0] * (f_wall[0] + f_wall[1]) / 2, 1e-5 * k[0]);
    CLOSE(k[7], k0[7] * (f_wall[3] + f_wall[4]) / 2, 1e-5 * k[7]);
    CHECK(k[0] == k[1] && k[2] == k[3] && k[4] == k[5] && k[6] == k[7]);
    memcpy(k0, k, sizeof k);
    d[2] = 0;
    EXPECT(FN(dk_spring_scale_stiffness)(&chain_graph, d, 5, k, 8),
           DK_ERR_NON_POSITIVE);
    EXPECT(FN(dk_spring_scale_stiffness)(&chain_graph, d, 4, k, 8),
           DK_ERR_LENGTH_MISMATCH);
    SAME(k, k0, sizeof k);

    /* Dual volumes of two triangles of the unit square: 1/3 at the shared corners, 1/6 else. */
    OK(FN(dk_spring_dual_volumes)(&tris, 0, NULL, 0, square, 8, 2, v, 4, cs, 2));
    CLOSE(v[0], 1.0 / 3, 1e-6);
    CLOSE(v[1], 1.0 / 6, 1e-6);
    CLOSE(v[2], 1.0 / 3, 1e-6);
    CLOSE(v[3], 1.0 / 6, 1e-6);
    OK(FN(dk_spring_dual_volumes)(&tris1, 1, iscr, ISCR_LEN, square, 8, 2, d0, 4, cs, 2));
    SAME(v, d0, sizeof v);
    EXPECT(FN(dk_spring_dual_volumes)(&tris, 0, NULL, 0, square, 8, 2, d0, 4, cs, 1),
           DK_ERR_BUFFER_TOO_SMALL);
    /* Inverse-volume factors mean / v, mean 1/4: 3/4 and 3/2. */
    OK(FN(dk_spring_inverse_volume_factors)(v, 4, 1));
    CLOSE(v[0], 0.75, 1e-6);
    CLOSE(v[1], 1.5, 1e-6);
}

static void CAT(run_, SUF)(void) {
    CAT(stiffening_, SUF)();
    CAT(taubin_params_, SUF)();
    CAT(taubin_smooth_arclength_, SUF)();
    CAT(taubin_structured_, SUF)();
    CAT(taubin_graph_, SUF)();
    CAT(taubin_lines_, SUF)();
    CAT(springs_linear_, SUF)();
    CAT(springs_angle_, SUF)();
    CAT(quality_, SUF)();
}

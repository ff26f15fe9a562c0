/* The per-precision part of slide.c: included once with REAL double (FN(name) = name, SUF f64,
 * HEX hex64, TOL 1e-12) and once with REAL float (FN(name) = name_f32, SUF f32, HEX hex32,
 * TOL 1e-6). */

/* A call that must fail with `status` and leave the values (vb, a copy of v0) and the report
 * (rb) bit-for-bit untouched. */
#define BAD(call, status)                                                                 \
    do {                                                                                  \
        memcpy(vb, v0, 2 * N * sizeof(REAL));                                             \
        POISON(rb);                                                                       \
        memcpy(&rb0, &rb, sizeof rb);                                                     \
        EXPECT(call, status);                                                             \
        SAME(vb, v0, 2 * N * sizeof(REAL));                                               \
        SAME(&rb, &rb0, sizeof rb);                                                       \
    } while (0)

#define BAD_LIN(sysp, conp, optp, dim, slen, status)                                       \
    BAD(FN(dk_spring_solve_linear_sliding)((sysp), (conp), (optp), (dim), vb, 2 * N,        \
                                           scratch, (slen), iscr, N, &rb),                 \
        status)
#define BAD_ANG(sysp, conp, optp, omega, slen, status)                                     \
    BAD(FN(dk_spring_solve_angle_sliding)((sysp), pts, 2 * N, 2, (conp), (optp), (omega),   \
                                          vb, 2 * N, scratch, (slen), iscr, N, &rb),       \
        status)
#define BAD_LAMG(sysp, conp, poolsp, status)                                               \
    BAD(FN(dk_spring_solve_linear_sliding_amg)((sysp), (conp), &o, &amg, 2, vb, 2 * N,      \
                                               (poolsp), &rb),                             \
        status)
#define BAD_AAMG(sysp, conp, optp, poolsp, status)                                         \
    BAD(FN(dk_spring_solve_angle_sliding_amg)((sysp), pts, 2 * N, 2, (conp), (optp), &amg,  \
                                              vb, 2 * N, (poolsp), &rb),                   \
        status)

/* A dk_fit_plane call that must fail with `status` and leave its outputs untouched. */
#define BAD_FIT(call, status)                                                             \
    do {                                                                                  \
        POISON(fb);                                                                       \
        memcpy(&fb0, &fb, sizeof fb);                                                     \
        EXPECT(call, status);                                                             \
        SAME(&fb, &fb0, sizeof fb);                                                       \
    } while (0)

/* Prints a solve's iterations, report and values. */
static void CAT(print_, SUF)(const char *what, const dk_spring_solve_report *r, const REAL *v) {
    char name[64];
    double rep[2];
    printf("%s_%s %zu %d\n", what, STR(SUF), r->iterations, (int)r->converged);
    rep[0] = r->residual;
    rep[1] = r->max_update;
    snprintf(name, sizeof name, "%s_report_%s", what, STR(SUF));
    hex64(name, rep, 2);
    snprintf(name, sizeof name, "%s_values_%s", what, STR(SUF));
    HEX(name, v, 2 * N);
}

/* Fixed nodes keep their values; every sliding node's displacement lies on the line
 * (|n.d| <= TOL |d|), and some sliding node moved. */
static void CAT(check_slid_, SUF)(const REAL *n, const REAL *v, const REAL *v0) {
    size_t i, moved = 0;
    for (i = 0; i < N; i++) {
        double dx = (double)v[2 * i], dy = (double)v[2 * i + 1];
        if (kinds[i] == 1) CHECK(v[2 * i] == v0[2 * i] && v[2 * i + 1] == v0[2 * i + 1]);
        if (kinds[i] == 2) {
            double dot = (double)n[0] * dx + (double)n[1] * dy, len = sqrt(dx * dx + dy * dy);
            CHECK(fabs(dot) <= TOL * len);
            moved += len > 1e-3;
        }
    }
    CHECK(moved >= NSYM / 2);
}

static void CAT(run_, SUF)(void) {
    REAL *pts = xmalloc(2 * N * sizeof(REAL)), *k = xmalloc(used * sizeof(REAL));
    REAL *v0 = xmalloc(2 * N * sizeof(REAL)), *v = xmalloc(2 * N * sizeof(REAL));
    REAL *vb = xmalloc(2 * N * sizeof(REAL)), *vcg = xmalloc(2 * N * sizeof(REAL));
    REAL *dirs = xmalloc(2 * N * sizeof(REAL)), *dnu = xmalloc(2 * N * sizeof(REAL));
    REAL *dnan = xmalloc(2 * N * sizeof(REAL)), *moved = xmalloc(2 * N * sizeof(REAL));
    REAL *mb = xmalloc(2 * N * sizeof(REAL)), *orig_nan = xmalloc(2 * N * sizeof(REAL));
    REAL *scratch = xmalloc(12 * N * sizeof(REAL)), *reals;
    uint32_t *iscr = xmalloc(N * sizeof(uint32_t)), *indices, *work;
    uint32_t few[1], out_of_range[NSYM], inner[NT];
    uint8_t *mask = xmalloc(N), *pinned = xmalloc(N), *kinds4 = xmalloc(N), *m7 = xmalloc(N);
    struct {
        REAL normal[2], centre[2], residual, extent;
    } fit, fb, fb0;
    FN(dk_constraints) con, con_short, con_odd, con_dshort, con_nullkinds, con_kind4,
        con_notunit, con_nan;
    const FN(dk_constraints) *badc[9];
    int32_t bads[9];
    FN(dk_spring_system) sys, sys_pinned;
    FN(dk_plan_pools) pools, p;
    dk_spring_solve_options o, ob;
    dk_spring_angle_options ao, aob;
    dk_amg_options amg;
    dk_plan_sizes sl, sla, lin, sz, sz0;
    dk_spring_solve_report r, rb, rb0;
    size_t i, need, work_len, first_sliding = 0;
    const REAL tol = (REAL)1e-4;
    char name[64];

    for (i = 0; i < 2 * N; i++) {
        pts[i] = (REAL)points[i];
        v0[i] = (REAL)values0[i];
    }
    OK(FN(dk_spring_batina_stiffness)(&graph, pts, 2 * N, 2, 1, k, used));

    /* ---- The symmetry line: fitted, 0- and 1-based give the same bits. ---- */
    OK(FN(dk_fit_plane)(pts, 2 * N, 2, sym, NSYM, 0, tol, NULL, 0, fit.normal, 2, fit.centre,
                        2, &fit.residual, &fit.extent));
    snprintf(name, sizeof name, "fit_%s", STR(SUF));
    HEX(name, &fit.normal[0], 6);
    CHECK(fabs((double)fit.normal[0] * fit.normal[0] + (double)fit.normal[1] * fit.normal[1] -
               1) < 1e-6);
    CHECK(fit.residual <= tol * fit.extent && fit.extent > 1.9);
    POISON(fb);
    OK(FN(dk_fit_plane)(pts, 2 * N, 2, sym1, NSYM, 1, tol, iscr, NSYM, fb.normal, 2, fb.centre,
                        2, &fb.residual, &fb.extent));
    SAME(&fb, &fit, sizeof fit);
    BAD_FIT(FN(dk_fit_plane)(pts, 2 * N, 2, sym1, NSYM, 1, tol, iscr, NSYM - 1, fb.normal, 2,
                             fb.centre, 2, &fb.residual, &fb.extent),
            DK_ERR_BUFFER_TOO_SMALL);
    BAD_FIT(FN(dk_fit_plane)(pts, 2 * N, 2, sym, NSYM, 2, tol, iscr, NSYM, fb.normal, 2,
                             fb.centre, 2, &fb.residual, &fb.extent),
            DK_ERR_BAD_INDEX_BASE);
    BAD_FIT(FN(dk_fit_plane)(pts, 2 * N, 2, sym, NSYM, 0, tol, NULL, 0, fb.normal, 3, fb.centre,
                             2, &fb.residual, &fb.extent),
            DK_ERR_LENGTH_MISMATCH);
    BAD_FIT(FN(dk_fit_plane)(pts, 2 * N, 2, sym, NSYM, 0, tol, NULL, 0, fb.normal, 2, fb.centre,
                             1, &fb.residual, &fb.extent),
            DK_ERR_LENGTH_MISMATCH);

    /* ---- Plane intersection: the unit tangent (a x b) / |a x b|, whatever the normals'
     * lengths; parallel, zero or non-finite normals fail and leave the output untouched. ---- */
    {
        const REAL z[3] = {0, 0, 2}, x[3] = {3, 0, 0}, mz[3] = {0, 0, -5}, zero[3] = {0, 0, 0};
        const REAL d[3] = {1, 1, 0}, bad[3] = {0, (REAL)NAN, 1};
        REAL t[3], t0[3];
        OK(FN(dk_plane_intersection)(z, x, t)); /* z x x = y */
        CHECK(t[0] == 0 && t[1] == 1 && t[2] == 0);
        OK(FN(dk_plane_intersection)(d, z, t)); /* (1, 1, 0) / sqrt 2 x z = (1, -1, 0) / sqrt 2 */
        CHECK(fabs(t[0] - sqrt(0.5)) < TOL && fabs(t[1] + sqrt(0.5)) < TOL && t[2] == 0);
        POISON(t);
        memcpy(t0, t, sizeof t);
        EXPECT(FN(dk_plane_intersection)(z, mz, t), DK_ERR_ZERO_LENGTH);
        EXPECT(FN(dk_plane_intersection)(zero, x, t), DK_ERR_ZERO_LENGTH);
        EXPECT(FN(dk_plane_intersection)(bad, x, t), DK_ERR_NON_FINITE);
        EXPECT(FN(dk_plane_intersection)(z, NULL, t), DK_ERR_NULL_POINTER);
        EXPECT(FN(dk_plane_intersection)(z, x, NULL), DK_ERR_NULL_POINTER);
        SAME(t, t0, sizeof t);
    }
    BAD_FIT(FN(dk_fit_plane)(pts, 2 * N, 2, sym, NSYM, 0, tol, NULL, 0, fb.normal, 2, fb.centre,
                             2, NULL, &fb.extent),
            DK_ERR_NULL_POINTER);
    BAD_FIT(FN(dk_fit_plane)(pts, 2 * N, 2, sym, NSYM, 0, -tol, NULL, 0, fb.normal, 2,
                             fb.centre, 2, &fb.residual, &fb.extent),
            DK_ERR_INVALID_PARAMETER);
    BAD_FIT(FN(dk_fit_plane)(pts, 2 * N, 4, sym, NSYM, 0, tol, NULL, 0, fb.normal, 2, fb.centre,
                             2, &fb.residual, &fb.extent),
            DK_ERR_INVALID_PARAMETER);
    few[0] = sym[0];
    BAD_FIT(FN(dk_fit_plane)(pts, 2 * N, 2, few, 1, 0, tol, NULL, 0, fb.normal, 2, fb.centre, 2,
                             &fb.residual, &fb.extent),
            DK_ERR_INVALID_PARAMETER);
    memcpy(out_of_range, sym, sizeof sym);
    out_of_range[3] = N;
    BAD_FIT(FN(dk_fit_plane)(pts, 2 * N, 2, out_of_range, NSYM, 0, tol, NULL, 0, fb.normal, 2,
                             fb.centre, 2, &fb.residual, &fb.extent),
            DK_ERR_INDEX_OUT_OF_RANGE);
    for (i = 0; i < NT; i++) inner[i] = (uint32_t)i; /* the inner half circle: no line */
    BAD_FIT(FN(dk_fit_plane)(pts, 2 * N, 2, inner, NT, 0, tol, NULL, 0, fb.normal, 2, fb.centre,
                             2, &fb.residual, &fb.extent),
            DK_ERR_NOT_PLANAR);
    /* INFINITY never refuses. */
    OK(FN(dk_fit_plane)(pts, 2 * N, 2, inner, NT, 0, (REAL)INFINITY, NULL, 0, fb.normal, 2,
                        fb.centre, 2, &fb.residual, &fb.extent));
    CHECK(fb.residual > 0.1);

    /* ---- The constraints: directions of free and fixed nodes are never read. ---- */
    for (i = 0; i < N; i++) {
        REAL junk = kinds[i] == 0 ? (REAL)NAN : (REAL)INFINITY;
        dirs[2 * i] = kinds[i] == 2 ? fit.normal[0] : junk;
        dirs[2 * i + 1] = kinds[i] == 2 ? fit.normal[1] : junk;
        if (kinds[i] == 2 && !first_sliding) first_sliding = i;
    }
    CHECK(first_sliding > 0);
    con.kinds = kinds;
    con.kinds_len = N;
    con.directions = dirs;
    con.directions_len = 2 * N;
    con_short = con;
    con_short.kinds_len = N - 1;
    con_short.directions_len = 2 * N - 2;
    con_odd = con;
    con_odd.directions_len = 2 * N - 1;
    con_dshort = con;
    con_dshort.directions_len = 2 * N - 2;
    con_nullkinds = con;
    con_nullkinds.kinds = NULL;
    memcpy(kinds4, kinds, N);
    kinds4[N / 2] = 4;
    con_kind4 = con;
    con_kind4.kinds = kinds4;
    memcpy(dnu, dirs, 2 * N * sizeof(REAL));
    dnu[2 * first_sliding] *= (REAL)1.01;
    dnu[2 * first_sliding + 1] *= (REAL)1.01;
    con_notunit = con;
    con_notunit.directions = dnu;
    memcpy(dnan, dirs, 2 * N * sizeof(REAL));
    dnan[2 * first_sliding + 1] = (REAL)NAN;
    con_nan = con;
    con_nan.directions = dnan;
    badc[0] = NULL;
    bads[0] = DK_ERR_NULL_POINTER;
    badc[1] = &con_short;
    bads[1] = DK_ERR_LENGTH_MISMATCH;
    badc[2] = &con_odd;
    bads[2] = DK_ERR_LENGTH_MISMATCH;
    badc[3] = &con_dshort;
    bads[3] = DK_ERR_LENGTH_MISMATCH;
    badc[4] = &con_nullkinds;
    bads[4] = DK_ERR_NULL_POINTER;
    badc[5] = &con_kind4;
    bads[5] = DK_ERR_INDEX_OUT_OF_RANGE;
    badc[6] = &con_notunit;
    bads[6] = DK_ERR_NOT_UNIT;
    badc[7] = &con_nan;
    bads[7] = DK_ERR_NON_FINITE;
    badc[8] = &con; /* with dim 3: the directions are not whole 3-vectors */
    bads[8] = DK_ERR_LENGTH_MISMATCH;

    /* The mask: 1 exactly at kind 1; written only on success. */
    memset(mask, 7, N);
    OK(FN(dk_constraints_fixed_mask)(&con, 2, mask, N));
    for (i = 0; i < N; i++) CHECK(mask[i] == (kinds[i] == 1));
    memset(m7, 7, N);
    memcpy(pinned, m7, N);
    EXPECT(FN(dk_constraints_fixed_mask)(&con, 2, pinned, N - 1), DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_constraints_fixed_mask)(&con, 2, pinned, N + 1), DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_constraints_fixed_mask)(&con, 4, pinned, N), DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_constraints_fixed_mask)(&con, 2, NULL, N), DK_ERR_NULL_POINTER);
    for (i = 0; i < 9; i++)
        EXPECT(FN(dk_constraints_fixed_mask)(badc[i], i == 8 ? 3 : 2, pinned, N), bads[i]);
    SAME(pinned, m7, N);
    /* A system that pins the sliding nodes does not match the constraints. */
    for (i = 0; i < N; i++) pinned[i] = (uint8_t)(kinds[i] != 0);
    sys.graph = graph;
    sys.stiffness = k;
    sys.stiffness_len = used;
    sys.fixed = mask;
    sys.fixed_len = N;
    sys_pinned = sys;
    sys_pinned.fixed = pinned;

    /* ---- Linear springs, CG + Jacobi and SOR. ---- */
    OK(FN(dk_spring_solve_options_default)(&o));
    OK(dk_spring_solve_linear_sliding_scratch_len(N, 2, &o, &need));
    CHECK(need == 12 * N);
    memcpy(v, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_linear_sliding)(&sys, &con, &o, 2, v, 2 * N, scratch, need, iscr, N,
                                          &r));
    CHECK(r.converged && r.residual <= o.residual_tol);
    CAT(check_slid_, SUF)(fit.normal, v, v0);
    CAT(print_, SUF)("lin_cg", &r, v);
    memcpy(vcg, v, 2 * N * sizeof(REAL));
    /* Scratch longer than needed: the same bits. */
    memcpy(vb, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_linear_sliding)(&sys, &con, &o, 2, vb, 2 * N, scratch, need + 3, iscr,
                                          N, &rb));
    SAME(vb, v, 2 * N * sizeof(REAL));
    for (i = 0; i < 9; i++)
        BAD_LIN(&sys, badc[i], &o, i == 8 ? 3 : 2, need, bads[i]);
    BAD_LIN(NULL, &con, &o, 2, need, DK_ERR_NULL_POINTER);
    BAD_LIN(&sys, &con, NULL, 2, need, DK_ERR_NULL_POINTER);
    BAD_LIN(&sys_pinned, &con, &o, 2, need, DK_ERR_INVALID_PARAMETER);
    BAD_LIN(&sys, &con, &o, 4, need, DK_ERR_INVALID_PARAMETER);
    BAD_LIN(&sys, &con, &o, 2, need - 1, DK_ERR_BUFFER_TOO_SMALL);
    BAD(FN(dk_spring_solve_linear_sliding)(&sys, &con, &o, 2, vb, 2 * N - 2, scratch, need,
                                           iscr, N, &rb),
        DK_ERR_LENGTH_MISMATCH);
    BAD(FN(dk_spring_solve_linear_sliding)(&sys, &con, &o, 2, vb, 2 * N, scratch, need, iscr,
                                           N - 1, &rb),
        DK_ERR_BUFFER_TOO_SMALL);
    ob = o;
    ob.residual_tol = -1;
    BAD_LIN(&sys, &con, &ob, 2, need, DK_ERR_INVALID_PARAMETER);
    ob = o;
    ob.preconditioner = 5;
    BAD_LIN(&sys, &con, &ob, 2, need, DK_ERR_INVALID_PARAMETER);
    memcpy(vb, v0, 2 * N * sizeof(REAL));
    EXPECT(FN(dk_spring_solve_linear_sliding)(&sys, &con, &o, 2, vb, 2 * N, scratch, need, iscr,
                                              N, NULL),
           DK_ERR_NULL_POINTER);
    SAME(vb, v0, 2 * N * sizeof(REAL));
    /* A NaN at a free node. */
    memcpy(mb, v0, 2 * N * sizeof(REAL));
    mb[2 * (NT + 5)] = (REAL)NAN;
    memcpy(vb, mb, 2 * N * sizeof(REAL));
    EXPECT(FN(dk_spring_solve_linear_sliding)(&sys, &con, &o, 2, vb, 2 * N, scratch, need, iscr,
                                              N, &rb),
           DK_ERR_NON_FINITE);
    SAME(vb, mb, 2 * N * sizeof(REAL));

    ob = o;
    ob.method = DK_LINEAR_SOR;
    ob.omega = 1.7;
    OK(dk_spring_solve_linear_sliding_scratch_len(N, 2, &ob, &need));
    CHECK(need == 2 * N);
    memcpy(v, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_linear_sliding)(&sys, &con, &ob, 2, v, 2 * N, scratch, need, iscr, N,
                                          &r));
    CHECK(r.converged);
    CAT(check_slid_, SUF)(fit.normal, v, v0);
    CAT(print_, SUF)("lin_sor", &r, v);
    for (i = 0; i < 2 * N; i++) CHECK(fabs((double)v[i] - (double)vcg[i]) <= 1e-3);
    BAD_LIN(&sys, &con, &ob, 2, need - 2, DK_ERR_BUFFER_TOO_SMALL);
    ob.omega = 2;
    BAD_LIN(&sys, &con, &ob, 2, need, DK_ERR_INVALID_PARAMETER);

    /* ---- Angle springs: direct Gauss-Seidel over-relaxed, and CG. ---- */
    OK(FN(dk_spring_angle_options_default)(&ao));
    ao.epsilon = 0.1;
    OK(FN(dk_spring_solve_angle_sliding_scratch_len)(N, 2, &ao, &need));
    CHECK(need == 2 * N);
    memcpy(v, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_angle_sliding)(&sys, pts, 2 * N, 2, &con, &ao, (REAL)1.5, v, 2 * N,
                                         scratch, need, iscr, N, &r));
    CHECK(r.converged);
    CAT(check_slid_, SUF)(fit.normal, v, v0);
    CAT(print_, SUF)("ang_sor", &r, v);
    for (i = 0; i < 9; i++)
        BAD(FN(dk_spring_solve_angle_sliding)(&sys, pts, 2 * N, i == 8 ? 3 : 2, badc[i], &ao,
                                              (REAL)1.5, vb, 2 * N, scratch, need, iscr, N,
                                              &rb),
            bads[i]);
    BAD_ANG(&sys_pinned, &con, &ao, (REAL)1.5, need, DK_ERR_INVALID_PARAMETER);
    BAD_ANG(&sys, &con, &ao, (REAL)2, need, DK_ERR_INVALID_PARAMETER);
    BAD_ANG(&sys, &con, &ao, (REAL)0, need, DK_ERR_INVALID_PARAMETER);
    BAD_ANG(&sys, &con, &ao, (REAL)1.5, need - 2, DK_ERR_BUFFER_TOO_SMALL);
    BAD_ANG(&sys, &con, NULL, (REAL)1.5, need, DK_ERR_NULL_POINTER);
    BAD_ANG(NULL, &con, &ao, (REAL)1.5, need, DK_ERR_NULL_POINTER);
    aob = ao;
    aob.epsilon = -1;
    BAD_ANG(&sys, &con, &aob, (REAL)1.5, need, DK_ERR_INVALID_PARAMETER);
    aob = ao;
    aob.method = 7;
    BAD_ANG(&sys, &con, &aob, (REAL)1.5, need, DK_ERR_INVALID_PARAMETER);
    BAD(FN(dk_spring_solve_angle_sliding)(&sys, NULL, 2 * N, 2, &con, &ao, (REAL)1.5, vb, 2 * N,
                                          scratch, need, iscr, N, &rb),
        DK_ERR_NULL_POINTER);

    ao.method = DK_ANGLE_CG;
    OK(FN(dk_spring_solve_angle_sliding_scratch_len)(N, 2, &ao, &need));
    CHECK(need == 10 * N);
    memcpy(v, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_angle_sliding)(&sys, pts, 2 * N, 2, &con, &ao, (REAL)1, v, 2 * N,
                                         scratch, need, iscr, N, &r));
    CHECK(r.converged && r.residual <= ao.residual_tol);
    CAT(check_slid_, SUF)(fit.normal, v, v0);
    CAT(print_, SUF)("ang_cg", &r, v);
    memcpy(vcg, v, 2 * N * sizeof(REAL));
    BAD_ANG(&sys, &con, &ao, (REAL)1, need - 1, DK_ERR_BUFFER_TOO_SMALL);

    /* ---- Multigrid: pools sized exactly, the hierarchy set up in them every call. ---- */
    OK(dk_amg_options_default(&amg));
    OK(dk_spring_amg_work_len(N, used, &work_len));
    work = xmalloc(work_len * sizeof *work);
    OK(FN(dk_spring_solve_linear_sliding_amg_pool_sizes)(&sys, 2, &amg, work, work_len, &sl));
    OK(FN(dk_spring_solve_angle_sliding_amg_pool_sizes)(&sys, 2, &amg, work, work_len, &sla));
    OK(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 2, &amg, work, work_len, &lin));
    printf("sizes_%s %zu %zu %zu %zu\n", STR(SUF), work_len, sl.reals, sl.indices, sl.bytes);
    CHECK(sla.reals == sl.reals && sla.indices == sl.indices && sla.bytes == 0);
    /* One more fine-level vector per component than the unconstrained solve. */
    CHECK(sl.reals == lin.reals + 2 * N && sl.indices == lin.indices && sl.bytes == 0);
    POISON(sz);
    memcpy(&sz0, &sz, sizeof sz);
    EXPECT(FN(dk_spring_solve_linear_sliding_amg_pool_sizes)(&sys, 2, &amg, work, work_len - 1,
                                                             &sz),
           DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(FN(dk_spring_solve_angle_sliding_amg_pool_sizes)(&sys, 4, &amg, work, work_len, &sz),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_spring_solve_linear_sliding_amg_pool_sizes)(&sys, 1, &amg, work, work_len, &sz),
           DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_spring_solve_linear_sliding_amg_pool_sizes)(NULL, 2, &amg, work, work_len, &sz),
           DK_ERR_NULL_POINTER);
    SAME(&sz, &sz0, sizeof sz);
    reals = xmalloc(sl.reals * sizeof(REAL));
    indices = xmalloc(sl.indices * sizeof(uint32_t));
    pools.reals = reals;
    pools.reals_len = sl.reals;
    pools.indices = indices;
    pools.indices_len = sl.indices;
    pools.bytes = NULL;
    pools.bytes_len = 0;

    memcpy(v, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_linear_sliding_amg)(&sys, &con, &o, &amg, 2, v, 2 * N, &pools, &r));
    CHECK(r.converged && r.residual <= o.residual_tol);
    CAT(check_slid_, SUF)(fit.normal, v, v0);
    CAT(print_, SUF)("lin_amg", &r, v);
    for (i = 0; i < 9; i++)
        BAD(FN(dk_spring_solve_linear_sliding_amg)(&sys, badc[i], &o, &amg, i == 8 ? 3 : 2, vb,
                                                   2 * N, &pools, &rb),
            bads[i]);
    BAD_LAMG(&sys_pinned, &con, &pools, DK_ERR_INVALID_PARAMETER);
    BAD_LAMG(NULL, &con, &pools, DK_ERR_NULL_POINTER);
    BAD_LAMG(&sys, &con, NULL, DK_ERR_NULL_POINTER);
    p = pools;
    p.reals_len = sl.reals - 1;
    BAD_LAMG(&sys, &con, &p, DK_ERR_BUFFER_TOO_SMALL);
    p.reals_len = lin.reals; /* the unconstrained solve's length is too short */
    BAD_LAMG(&sys, &con, &p, DK_ERR_BUFFER_TOO_SMALL);
    p = pools;
    p.indices_len = sl.indices - 1;
    BAD_LAMG(&sys, &con, &p, DK_ERR_BUFFER_TOO_SMALL);
    BAD(FN(dk_spring_solve_linear_sliding_amg)(&sys, &con, &o, &amg, 4, vb, 2 * N, &pools, &rb),
        DK_ERR_INVALID_PARAMETER);

    ao.epsilon = 0.1;
    memcpy(v, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_angle_sliding_amg)(&sys, pts, 2 * N, 2, &con, &ao, &amg, v, 2 * N,
                                             &pools, &r));
    CHECK(r.converged && r.residual <= ao.residual_tol);
    CAT(check_slid_, SUF)(fit.normal, v, v0);
    CAT(print_, SUF)("ang_amg", &r, v);
    /* The same problem as the node-block CG above. */
    for (i = 0; i < 2 * N; i++) CHECK(fabs((double)v[i] - (double)vcg[i]) <= 1e-3);
    for (i = 0; i < 9; i++)
        BAD(FN(dk_spring_solve_angle_sliding_amg)(&sys, pts, 2 * N, i == 8 ? 3 : 2, badc[i], &ao,
                                                  &amg, vb, 2 * N, &pools, &rb),
            bads[i]);
    BAD_AAMG(&sys_pinned, &con, &ao, &pools, DK_ERR_INVALID_PARAMETER);
    BAD_AAMG(&sys, &con, NULL, &pools, DK_ERR_NULL_POINTER);
    p = pools;
    p.reals_len = sla.reals - 1;
    BAD_AAMG(&sys, &con, &ao, &p, DK_ERR_BUFFER_TOO_SMALL);
    aob = ao;
    aob.epsilon = NAN;
    BAD_AAMG(&sys, &con, &aob, &pools, DK_ERR_INVALID_PARAMETER);

    /* ---- dk_slide_points after a propagation that moved every node. ---- */
    for (i = 0; i < N; i++) {
        moved[2 * i] = pts[2 * i] + (REAL)(0.01 * (double)(i % 7));
        moved[2 * i + 1] = pts[2 * i + 1] + (REAL)(0.02 * (double)(i % 5));
    }
    memcpy(mb, moved, 2 * N * sizeof(REAL));
    OK(FN(dk_slide_points)(&con, 2, pts, 2 * N, moved, 2 * N));
    snprintf(name, sizeof name, "slid_points_%s", STR(SUF));
    HEX(name, moved, 2 * N);
    for (i = 0; i < N; i++) {
        if (kinds[i] == 2) {
            double dx = (double)moved[2 * i] - pts[2 * i], dy = (double)moved[2 * i + 1] -
                                                                 pts[2 * i + 1];
            CHECK(fabs((double)fit.normal[0] * dx + (double)fit.normal[1] * dy) <=
                  TOL * sqrt(dx * dx + dy * dy) + 4 * TOL);
        } else {
            CHECK(moved[2 * i] == mb[2 * i] && moved[2 * i + 1] == mb[2 * i + 1]);
        }
    }
    memcpy(orig_nan, pts, 2 * N * sizeof(REAL));
    orig_nan[7] = (REAL)NAN;
    memcpy(moved, mb, 2 * N * sizeof(REAL));
    EXPECT(FN(dk_slide_points)(&con, 2, orig_nan, 2 * N, moved, 2 * N), DK_ERR_NON_FINITE);
    EXPECT(FN(dk_slide_points)(&con, 2, pts, 2 * N - 2, moved, 2 * N), DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_slide_points)(&con, 2, pts, 2 * N, moved, 2 * N - 2), DK_ERR_LENGTH_MISMATCH);
    EXPECT(FN(dk_slide_points)(&con, 2, NULL, 2 * N, moved, 2 * N), DK_ERR_NULL_POINTER);
    EXPECT(FN(dk_slide_points)(&con, 4, pts, 2 * N, moved, 2 * N), DK_ERR_INVALID_PARAMETER);
    for (i = 0; i < 9; i++)
        EXPECT(FN(dk_slide_points)(badc[i], i == 8 ? 3 : 2, pts, 2 * N, moved, 2 * N), bads[i]);
    SAME(moved, mb, 2 * N * sizeof(REAL));

    free(pts);
    free(k);
    free(v0);
    free(v);
    free(vb);
    free(vcg);
    free(dirs);
    free(dnu);
    free(dnan);
    free(moved);
    free(mb);
    free(orig_nan);
    free(scratch);
    free(reals);
    free(indices);
    free(work);
    free(iscr);
    free(mask);
    free(pinned);
    free(kinds4);
    free(m7);
}

#undef BAD
#undef BAD_LIN
#undef BAD_ANG
#undef BAD_LAMG
#undef BAD_AAMG
#undef BAD_FIT

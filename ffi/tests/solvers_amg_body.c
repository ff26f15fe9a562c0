/* The per-precision part of solvers_amg.c: included once with REAL double (FN(name) = name,
 * SUF f64, HEX hex64) and once with REAL float (FN(name) = name_f32, SUF f32, HEX hex32). */

/* One call of the linear solve that must fail with `status` and leave the values (a copy of
 * v0) and the report bit-for-bit untouched. */
#define BAD_LINEAR(sysp, optp, amgp, comps, vlen, poolsp, status)                            \
    do {                                                                                  \
        memcpy(vb, v0, 2 * N * sizeof(REAL));                                             \
        POISON(rb);                                                                       \
        memcpy(&rb0, &rb, sizeof rb);                                                     \
        EXPECT(FN(dk_spring_solve_linear_amg)((sysp), (optp), (amgp), (comps), vb, (vlen),   \
                                              (poolsp), &rb),                             \
               (status));                                                                 \
        SAME(vb, v0, 2 * N * sizeof(REAL));                                               \
        SAME(&rb, &rb0, sizeof rb);                                                       \
    } while (0)

/* The same for the angle solve. */
#define BAD_ANGLE(sysp, ptsp, dim, optp, amgp, poolsp, status)                                \
    do {                                                                                  \
        memcpy(vb, v0, 2 * N * sizeof(REAL));                                             \
        POISON(rb);                                                                       \
        memcpy(&rb0, &rb, sizeof rb);                                                     \
        EXPECT(FN(dk_spring_solve_angle_amg)((sysp), (ptsp), 2 * N, (dim), (optp), (amgp),   \
                                             vb, 2 * N, (poolsp), &rb),                   \
               (status));                                                                 \
        SAME(vb, v0, 2 * N * sizeof(REAL));                                               \
        SAME(&rb, &rb0, sizeof rb);                                                       \
    } while (0)

/* A pool-size query that must fail with `status` and leave the sizes untouched. */
#define BAD_SIZES(call, status)                                                           \
    do {                                                                                  \
        POISON(sz);                                                                       \
        memcpy(&sz0, &sz, sizeof sz);                                                     \
        EXPECT(call, status);                                                             \
        SAME(&sz, &sz0, sizeof sz);                                                       \
    } while (0)

static void CAT(run_, SUF)(void) {
    REAL *pts = xmalloc(2 * N * sizeof(REAL)), *k = xmalloc(used * sizeof(REAL));
    REAL *kbad = xmalloc(used * sizeof(REAL));
    REAL *v0 = xmalloc(2 * N * sizeof(REAL)), *v = xmalloc(2 * N * sizeof(REAL));
    REAL *vb = xmalloc(2 * N * sizeof(REAL)), *vn = xmalloc(2 * N * sizeof(REAL));
    REAL *reals, *scratch;
    uint32_t *indices, *work, *iscr = xmalloc(N * sizeof(uint32_t));
    uint8_t *free_mask = xmalloc(N);
    const FN(dk_spring_system) sys = {graph, k, used, fixed, N};
    const FN(dk_spring_system) asym = {graph, kbad, used, fixed, N};
    const FN(dk_spring_system) unanchored = {graph, k, used, free_mask, N};
    const FN(dk_spring_system) short_fixed = {graph, k, used, fixed, N - 1};
    dk_amg_options amg, bad;
    dk_spring_solve_options o, ob;
    dk_spring_angle_options ao, aob;
    dk_plan_sizes lin, lin1, ang, sz, sz0;
    dk_spring_solve_report r, r1, rb, rb0;
    FN(dk_plan_pools) pools, p;
    size_t work_len, hier_values, items, need, i;
    uint8_t bytes[4];
    char name[64];

    for (i = 0; i < 2 * N; i++) {
        pts[i] = (REAL)points[i];
        v0[i] = (REAL)values0[i];
    }
    memset(free_mask, 0, N);
    OK(FN(dk_spring_batina_stiffness)(&graph, pts, 2 * N, 2, 1, k, used));
    memcpy(kbad, k, used * sizeof(REAL));
    kbad[0] *= 2;
    OK(dk_amg_options_default(&amg));
    OK(FN(dk_spring_solve_options_default)(&o));
    OK(FN(dk_spring_angle_options_default)(&ao));
    ao.method = DK_ANGLE_CG;
    ao.epsilon = 0.1;

    /* ---- Sizes: symbolic first. ---- */
    OK(dk_spring_amg_work_len(N, used, &work_len));
    CHECK(work_len == 4 * (N + used) + 64);
    work = xmalloc(work_len * sizeof *work);
    OK(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 2, &amg, work, work_len, &lin));
    OK(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 1, &amg, work, work_len, &lin1));
    OK(FN(dk_spring_solve_angle_amg_pool_sizes)(&sys, 2, &amg, work, work_len, &ang));
    printf("sizes_%s %zu %zu %zu %zu %zu\n", STR(SUF), work_len, lin.reals, lin.indices,
           lin.bytes, lin1.reals);
    CHECK(lin.bytes == 0 && lin1.bytes == 0 && lin.indices == lin1.indices);
    CHECK(ang.reals == lin.reals && ang.indices == lin.indices && ang.bytes == 0);
    CHECK(lin.indices > work_len);
    /* reals = hierarchy values + items * components: the two queries give both parts. */
    items = lin.reals - lin1.reals;
    hier_values = lin1.reals - items;
    CHECK(items >= 5 * (size_t)N && items < 6 * (size_t)N && hier_values > 0);

    BAD_SIZES(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 2, &amg, work, work_len - 1, &sz),
              DK_ERR_BUFFER_TOO_SMALL);
    BAD_SIZES(FN(dk_spring_solve_angle_amg_pool_sizes)(&sys, 2, &amg, work, work_len - 1, &sz),
              DK_ERR_BUFFER_TOO_SMALL);
    BAD_SIZES(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 2, &amg, work, N - 1, &sz),
              DK_ERR_BUFFER_TOO_SMALL);
    BAD_SIZES(FN(dk_spring_solve_linear_amg_pool_sizes)(NULL, 2, &amg, work, work_len, &sz),
              DK_ERR_NULL_POINTER);
    BAD_SIZES(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 2, NULL, work, work_len, &sz),
              DK_ERR_NULL_POINTER);
    BAD_SIZES(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 2, &amg, NULL, work_len, &sz),
              DK_ERR_NULL_POINTER);
    BAD_SIZES(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 0, &amg, work, work_len, &sz),
              DK_ERR_INVALID_PARAMETER);
    BAD_SIZES(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 8, &amg, work, work_len, &sz),
              DK_ERR_INVALID_PARAMETER);
    BAD_SIZES(FN(dk_spring_solve_angle_amg_pool_sizes)(&sys, 4, &amg, work, work_len, &sz),
              DK_ERR_INVALID_PARAMETER);
    BAD_SIZES(FN(dk_spring_solve_linear_amg_pool_sizes)(&asym, 2, &amg, work, work_len, &sz),
              DK_ERR_NOT_SYMMETRIC);
    BAD_SIZES(FN(dk_spring_solve_linear_amg_pool_sizes)(&unanchored, 2, &amg, work, work_len,
                                                        &sz),
              DK_ERR_UNANCHORED);
    bad = amg;
    bad.max_levels = 0;
    BAD_SIZES(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 2, &bad, work, work_len, &sz),
              DK_ERR_INVALID_PARAMETER);
    bad = amg;
    bad.smoother = 7;
    BAD_SIZES(FN(dk_spring_solve_angle_amg_pool_sizes)(&sys, 2, &bad, work, work_len, &sz),
              DK_ERR_INVALID_PARAMETER);
    EXPECT(FN(dk_spring_solve_linear_amg_pool_sizes)(&sys, 2, &amg, work, work_len, NULL),
           DK_ERR_NULL_POINTER);

    /* ---- The linear solve in pools of exactly the queried lengths. ---- */
    reals = xmalloc((lin.reals + 5) * sizeof(REAL));
    indices = xmalloc((lin.indices + 3) * sizeof(uint32_t));
    pools.reals = reals;
    pools.reals_len = lin.reals;
    pools.indices = indices;
    pools.indices_len = lin.indices;
    pools.bytes = NULL;
    pools.bytes_len = 0;
    memcpy(v, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_linear_amg)(&sys, &o, &amg, 2, v, 2 * N, &pools, &r));
    CHECK(r.converged && r.iterations > 0 && r.residual <= o.residual_tol);
    for (i = 0; i < N; i++)
        if (fixed[i]) CHECK(v[2 * i] == v0[2 * i] && v[2 * i + 1] == v0[2 * i + 1]);
    printf("linear_%s %zu %d\n", STR(SUF), r.iterations, (int)r.converged);
    {
        double rep[2];
        rep[0] = r.residual;
        rep[1] = r.max_update;
        snprintf(name, sizeof name, "linear_report_%s", STR(SUF));
        hex64(name, rep, 2);
    }
    snprintf(name, sizeof name, "linear_values_%s", STR(SUF));
    HEX(name, v, 2 * N);

    /* Longer pools and a bytes buffer give the same bits. */
    p = pools;
    p.reals_len = lin.reals + 5;
    p.indices_len = lin.indices + 3;
    p.bytes = bytes;
    p.bytes_len = 4;
    memcpy(vb, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_linear_amg)(&sys, &o, &amg, 2, vb, 2 * N, &p, &rb));
    SAME(vb, v, 2 * N * sizeof(REAL));
    CHECK(rb.iterations == r.iterations && rb.residual == r.residual);

    /* The one-level method of dk_spring_solve_linear (CG + Jacobi) on the same problem. */
    OK(dk_spring_solve_linear_scratch_len(N, 2, &o, &need));
    scratch = xmalloc(need * sizeof(REAL));
    memcpy(vn, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_linear)(&sys, &o, 2, vn, 2 * N, scratch, need, iscr, N, &r1));
    CHECK(r1.converged);
    printf("cg_linear_%s %zu\n", STR(SUF), r1.iterations);
    CHECK(4 * r.iterations <= r1.iterations);
    for (i = 0; i < 2 * N; i++) CHECK(fabs((double)vn[i] - (double)v[i]) <= 1e-3);
    free(scratch);

    /* Bad input: values and report untouched. */
    BAD_LINEAR(NULL, &o, &amg, 2, 2 * N, &pools, DK_ERR_NULL_POINTER);
    BAD_LINEAR(&sys, NULL, &amg, 2, 2 * N, &pools, DK_ERR_NULL_POINTER);
    BAD_LINEAR(&sys, &o, NULL, 2, 2 * N, &pools, DK_ERR_NULL_POINTER);
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, NULL, DK_ERR_NULL_POINTER);
    p = pools;
    p.reals_len = lin.reals - 1; /* the solve's scratch one scalar short */
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, &p, DK_ERR_BUFFER_TOO_SMALL);
    p.reals_len = hier_values; /* the hierarchy fits, no scratch */
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, &p, DK_ERR_BUFFER_TOO_SMALL);
    p.reals_len = hier_values - 1; /* the hierarchy's values one short */
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, &p, DK_ERR_BUFFER_TOO_SMALL);
    p.reals = NULL;
    p.reals_len = 0;
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, &p, DK_ERR_BUFFER_TOO_SMALL);
    p.reals_len = lin.reals;
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, &p, DK_ERR_NULL_POINTER);
    p = pools;
    p.indices_len = lin.indices - 1; /* the hierarchy's index entries one short */
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, &p, DK_ERR_BUFFER_TOO_SMALL);
    p.indices_len = work_len; /* the work fits, no hierarchy */
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, &p, DK_ERR_BUFFER_TOO_SMALL);
    p.indices_len = work_len - 1; /* the work one short */
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, &p, DK_ERR_BUFFER_TOO_SMALL);
    p.indices_len = N - 1; /* not even the system's validation fits */
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, &p, DK_ERR_BUFFER_TOO_SMALL);
    p = pools;
    p.bytes_len = 4; /* NULL with a length */
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N, &p, DK_ERR_NULL_POINTER);
    BAD_LINEAR(&sys, &o, &amg, 0, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    BAD_LINEAR(&sys, &o, &amg, 8, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N - 1, &pools, DK_ERR_LENGTH_MISMATCH);
    BAD_LINEAR(&sys, &o, &amg, 2, 2 * N - 2, &pools, DK_ERR_LENGTH_MISMATCH);
    BAD_LINEAR(&asym, &o, &amg, 2, 2 * N, &pools, DK_ERR_NOT_SYMMETRIC);
    BAD_LINEAR(&unanchored, &o, &amg, 2, 2 * N, &pools, DK_ERR_UNANCHORED);
    BAD_LINEAR(&short_fixed, &o, &amg, 2, 2 * N, &pools, DK_ERR_LENGTH_MISMATCH);
    bad = amg;
    bad.max_levels = 17;
    BAD_LINEAR(&sys, &o, &bad, 2, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    bad = amg;
    bad.max_coarse = 0;
    BAD_LINEAR(&sys, &o, &bad, 2, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    bad.max_coarse = 2049;
    BAD_LINEAR(&sys, &o, &bad, 2, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    bad = amg;
    bad.sweeps = 0;
    BAD_LINEAR(&sys, &o, &bad, 2, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    bad.sweeps = 17;
    BAD_LINEAR(&sys, &o, &bad, 2, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    bad = amg;
    bad.smoother = 2;
    BAD_LINEAR(&sys, &o, &bad, 2, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    bad = amg;
    bad.strength_theta = 1;
    BAD_LINEAR(&sys, &o, &bad, 2, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    bad.strength_theta = -0.25;
    BAD_LINEAR(&sys, &o, &bad, 2, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    bad.strength_theta = NAN;
    BAD_LINEAR(&sys, &o, &bad, 2, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    ob = o;
    ob.residual_tol = -1;
    BAD_LINEAR(&sys, &ob, &amg, 2, 2 * N, &pools, DK_ERR_INVALID_PARAMETER);
    /* A NULL report: values untouched. */
    memcpy(vb, v0, 2 * N * sizeof(REAL));
    EXPECT(FN(dk_spring_solve_linear_amg)(&sys, &o, &amg, 2, vb, 2 * N, &pools, NULL),
           DK_ERR_NULL_POINTER);
    SAME(vb, v0, 2 * N * sizeof(REAL));
    /* A NaN at a free node. */
    memcpy(vn, v0, 2 * N * sizeof(REAL));
    vn[2 * (NI + 1)] = (REAL)NAN;
    memcpy(vb, vn, 2 * N * sizeof(REAL));
    POISON(rb);
    memcpy(&rb0, &rb, sizeof rb);
    EXPECT(FN(dk_spring_solve_linear_amg)(&sys, &o, &amg, 2, vb, 2 * N, &pools, &rb),
           DK_ERR_NON_FINITE);
    SAME(vb, vn, 2 * N * sizeof(REAL));
    SAME(&rb, &rb0, sizeof rb);
    /* After all that, the same pools still give the same bits. */
    memcpy(vb, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_linear_amg)(&sys, &o, &amg, 2, vb, 2 * N, &pools, &rb));
    SAME(vb, v, 2 * N * sizeof(REAL));

    /* ---- The angle springs (epsilon 0.1), the same pools (V = dim = 2). ---- */
    memcpy(v, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_angle_amg)(&sys, pts, 2 * N, 2, &ao, &amg, v, 2 * N, &pools, &r));
    CHECK(r.converged && r.iterations > 0 && r.residual <= ao.residual_tol);
    printf("angle_%s %zu %d\n", STR(SUF), r.iterations, (int)r.converged);
    {
        double rep[2];
        rep[0] = r.residual;
        rep[1] = r.max_update;
        snprintf(name, sizeof name, "angle_report_%s", STR(SUF));
        hex64(name, rep, 2);
    }
    snprintf(name, sizeof name, "angle_values_%s", STR(SUF));
    HEX(name, v, 2 * N);
    /* The direct method's options select the same solve (method is ignored). */
    aob = ao;
    aob.method = DK_ANGLE_DIRECT_GAUSS_SEIDEL;
    memcpy(vb, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_angle_amg)(&sys, pts, 2 * N, 2, &aob, &amg, vb, 2 * N, &pools, &rb));
    SAME(vb, v, 2 * N * sizeof(REAL));

    /* Block-Jacobi angle CG (DK_ANGLE_CG of dk_spring_solve_angle) on the same problem. */
    OK(FN(dk_spring_solve_angle_scratch_len)(N, 2, &ao, &need));
    scratch = xmalloc(need * sizeof(REAL));
    memcpy(vn, v0, 2 * N * sizeof(REAL));
    OK(FN(dk_spring_solve_angle)(&sys, pts, 2 * N, 2, &ao, vn, 2 * N, scratch, need, iscr, N,
                                 &r1));
    CHECK(r1.converged);
    printf("cg_angle_%s %zu\n", STR(SUF), r1.iterations);
    CHECK(4 * r.iterations <= r1.iterations);
    for (i = 0; i < 2 * N; i++) CHECK(fabs((double)vn[i] - (double)v[i]) <= 1e-3);
    free(scratch);

    BAD_ANGLE(NULL, pts, 2, &ao, &amg, &pools, DK_ERR_NULL_POINTER);
    BAD_ANGLE(&sys, NULL, 2, &ao, &amg, &pools, DK_ERR_NULL_POINTER);
    BAD_ANGLE(&sys, pts, 2, NULL, &amg, &pools, DK_ERR_NULL_POINTER);
    BAD_ANGLE(&sys, pts, 2, &ao, NULL, &pools, DK_ERR_NULL_POINTER);
    BAD_ANGLE(&sys, pts, 2, &ao, &amg, NULL, DK_ERR_NULL_POINTER);
    BAD_ANGLE(&sys, pts, 4, &ao, &amg, &pools, DK_ERR_INVALID_PARAMETER);
    p = pools;
    p.reals_len = ang.reals - 1;
    BAD_ANGLE(&sys, pts, 2, &ao, &amg, &p, DK_ERR_BUFFER_TOO_SMALL);
    p.reals_len = hier_values - 1;
    BAD_ANGLE(&sys, pts, 2, &ao, &amg, &p, DK_ERR_BUFFER_TOO_SMALL);
    p = pools;
    p.indices_len = ang.indices - 1;
    BAD_ANGLE(&sys, pts, 2, &ao, &amg, &p, DK_ERR_BUFFER_TOO_SMALL);
    p.indices_len = work_len - 1;
    BAD_ANGLE(&sys, pts, 2, &ao, &amg, &p, DK_ERR_BUFFER_TOO_SMALL);
    BAD_ANGLE(&asym, pts, 2, &ao, &amg, &pools, DK_ERR_NOT_SYMMETRIC);
    BAD_ANGLE(&unanchored, pts, 2, &ao, &amg, &pools, DK_ERR_UNANCHORED);
    aob = ao;
    aob.epsilon = -1;
    BAD_ANGLE(&sys, pts, 2, &aob, &amg, &pools, DK_ERR_INVALID_PARAMETER);
    aob = ao;
    aob.residual_tol = NAN;
    BAD_ANGLE(&sys, pts, 2, &aob, &amg, &pools, DK_ERR_INVALID_PARAMETER);
    bad = amg;
    bad.smoother = 9;
    BAD_ANGLE(&sys, pts, 2, &ao, &bad, &pools, DK_ERR_INVALID_PARAMETER);
    memcpy(vb, v0, 2 * N * sizeof(REAL));
    EXPECT(FN(dk_spring_solve_angle_amg)(&sys, pts, 2 * N, 2, &ao, &amg, vb, 2 * N, &pools,
                                         NULL),
           DK_ERR_NULL_POINTER);
    SAME(vb, v0, 2 * N * sizeof(REAL));

    free(pts);
    free(k);
    free(kbad);
    free(v0);
    free(v);
    free(vb);
    free(vn);
    free(reals);
    free(indices);
    free(work);
    free(iscr);
    free(free_mask);
}

#undef BAD_LINEAR
#undef BAD_ANGLE
#undef BAD_SIZES

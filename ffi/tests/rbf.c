/* RBF deformation from C: a ring "wall" turned by 20 degrees inside a fixed outer ring, with
 * Wendland C2 (every boundary node a centre, f64, index_base 0) and thin-plate splines
 * (greedy with the wall correction, f32, index_base 1). Prints the inputs and results as hex
 * bits for host-tests/tests/ffi/c_abi_rbf.rs, which compares them with the Rust API bit for
 * bit; then bad input (documented status, nothing written). */
#include <math.h>

#include "check.h"

#define NW 24         /* wall nodes */
#define NF 16         /* far-field nodes */
#define NB (NW + NF)
#define NV 40         /* volume points */
#define N (NB + NV)

int main(void) {
    static double points[2 * N], motion[2 * NB], disp[2 * N], scratch[20000];
    static float points32[2 * N], motion32[2 * NB], disp32[2 * N], scratch32[20000];
    static double wide[2 * N];
    static uint32_t boundary[NB], boundary1[NB], index[20000];
    const double pi = 3.14159265358979323846, c = cos(20.0 * pi / 180.0), s = sin(20.0 * pi / 180.0);
    dk_rbf_options o;
    dk_rbf_report report, untouched;
    size_t k, len, ilen;
    dk_status st;

    for (k = 0; k < NB; k++) {
        double t = 2.0 * pi * (double)k / (k < NW ? NW : NF);
        double r = k < NW ? 0.5 : 4.0;
        double x = r * cos(t), y = (k < NW ? 0.2 : 1.0) * r * sin(t);
        points[2 * k] = x;
        points[2 * k + 1] = y;
        motion[2 * k] = k < NW ? c * x - s * y - x : 0.0;
        motion[2 * k + 1] = k < NW ? s * x + c * y - y : 0.0;
        boundary[k] = (uint32_t)k;
        boundary1[k] = (uint32_t)k + 1;
    }
    for (k = 0; k < NV; k++) {
        double t = 2.399963229728653 * (double)k, r = 0.8 + 3.0 * (double)k / NV;
        points[2 * (NB + k)] = r * cos(t);
        points[2 * (NB + k) + 1] = r * sin(t);
    }
    for (k = 0; k < 2 * N; k++) points32[k] = (float)points[k];
    for (k = 0; k < 2 * NB; k++) motion32[k] = (float)motion[k];
    hex64("points", points, 2 * N);
    hex64("motion", motion, 2 * NB);

    /* Wendland C2, f64, every boundary node a centre, no correction. */
    OK(dk_rbf_options_default(&o));
    CHECK(o.kernel == DK_RBF_WENDLAND && o.max_centres == SIZE_MAX);
    o.radius = 3.0;
    OK(dk_rbf_scratch_len(NB, 2, &o, &len));
    CHECK(len <= 20000);
    OK(dk_rbf_index_scratch_len(NB, 2, 0, &o, &ilen));
    CHECK(ilen <= 20000);
    st = dk_rbf_deform(points, 2 * N, 2, boundary, NB, 0, motion, 2 * NB, &o, index, ilen,
                       scratch, len, disp, 2 * N, &report);
    CHECK(st == DK_OK);
    CHECK(report.centres == NB && report.dependent == 0);
    hex64("wendland", disp, 2 * N);
    hex64("wendland_error", &report.max_error, 1);

    /* Thin-plate splines, f32, greedy with the wall correction, 1-based boundary. */
    o.kernel = DK_RBF_THIN_PLATE;
    o.tolerance = 1e-3;
    o.max_centres = 30;
    o.correction_radius = 1.0;
    OK(dk_rbf_scratch_len(NB, 2, &o, &len));
    CHECK(len <= 20000);
    OK(dk_rbf_index_scratch_len(NB, 2, 1, &o, &ilen));
    CHECK(ilen <= 20000);
    st = dk_rbf_deform_f32(points32, 2 * N, 2, boundary1, NB, 1, motion32, 2 * NB, &o, index,
                           ilen, scratch32, len, disp32, 2 * N, &report);
    CHECK(st == DK_OK);
    CHECK(report.centres < NB);
    for (k = 0; k < 2 * NB; k++) CHECK(disp32[k] == motion32[k]); /* the wall is exact */
    for (k = 0; k < 2 * N; k++) wide[k] = (double)disp32[k];
    hex64("tps32", wide, 2 * N);
    printf("tps32_centres %zu\n", report.centres);

    /* Bad input: nothing written. */
    POISON(untouched);
    report = untouched;
    for (k = 0; k < 2 * N; k++) disp[k] = 7.0;
    o.kernel = 9;
    EXPECT(dk_rbf_deform(points, 2 * N, 2, boundary, NB, 0, motion, 2 * NB, &o, index, 20000,
                         scratch, 20000, disp, 2 * N, &report), DK_ERR_INVALID_PARAMETER);
    o.kernel = DK_RBF_WENDLAND;
    o.radius = -1.0;
    EXPECT(dk_rbf_deform(points, 2 * N, 2, boundary, NB, 0, motion, 2 * NB, &o, index, 20000,
                         scratch, 20000, disp, 2 * N, &report), DK_ERR_INVALID_PARAMETER);
    o.radius = 3.0;
    EXPECT(dk_rbf_deform(points, 2 * N, 2, boundary, NB, 0, motion, 2 * NB, &o, index, 20000,
                         scratch, 20000, disp, 2 * N, NULL), DK_ERR_NULL_POINTER);
    EXPECT(dk_rbf_deform(points, 2 * N, 2, boundary, NB, 0, motion, 2 * NB, &o, index, 3,
                         scratch, 20000, disp, 2 * N, &report), DK_ERR_BUFFER_TOO_SMALL);
    boundary[3] = N;
    EXPECT(dk_rbf_deform(points, 2 * N, 2, boundary, NB, 0, motion, 2 * NB, &o, index, 20000,
                         scratch, 20000, disp, 2 * N, &report), DK_ERR_INDEX_OUT_OF_RANGE);
    boundary[3] = 3;
    EXPECT(dk_rbf_deform(points, 2 * N, 4, boundary, NB, 0, motion, 2 * NB, &o, index, 20000,
                         scratch, 20000, disp, 2 * N, &report), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_rbf_scratch_len(NB, 2, NULL, &len), DK_ERR_NULL_POINTER);
    EXPECT(dk_rbf_index_scratch_len(NB, 2, 2, &o, &len), DK_ERR_BAD_INDEX_BASE);
    for (k = 0; k < 2 * N; k++) CHECK(disp[k] == 7.0);
    CHECK(memcmp(&report, &untouched, sizeof report) == 0);

    if (failures) return 1;
    printf("rbf: every check held\n");
    return 0;
}

/* Node orders from C99: dk_order_rcm, dk_order_hilbert (f64 and f32), dk_order_index_distance,
 * dk_order_permute (f64, f32; widths 1 and 2), dk_order_renumber (index_base 0 and 1),
 * dk_order_permute_graph with its edge map and dk_order_gather (f64, f32), on a 13 x 9 triangulated grid
 * whose nodes are numbered at random (an LCG shuffle).
 *
 * Prints the edges, the points and every order, key, distance and permuted graph, so
 * host-tests/tests/ffi/c_abi_order.rs can compute the same with the kernel and compare the
 * text. Checks here: every permutation applied and undone (order and inverse swapped) gives
 * back every bit; bad input (not a permutation, short keys, bad dim or width, an index out of
 * range, NULL) returns its status and leaves the outputs bit for bit untouched. Ends with
 * "order: every check held" (exit 0), or prints each failed check (exit 1). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#include "check.h"

#define NX 13
#define NY 9
#define N (NX * NY)
#define EDGES ((NX - 1) * NY + NX * (NY - 1) + (NX - 1) * (NY - 1))

static uint32_t label[N]; /* grid node -> its (random) index */
static uint32_t edges[2 * EDGES], offsets[N + 1], targets[2 * EDGES];
static size_t used;
static double points[2 * N];
static float points32[2 * N];

static void build(void) {
    uint64_t s = 12345;
    size_t i, j, e = 0;
    for (i = 0; i < N; i++) label[i] = (uint32_t)i;
    for (i = N - 1; i > 0; i--) {
        uint32_t t;
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        j = (size_t)((s >> 33) % (i + 1));
        t = label[i];
        label[i] = label[j];
        label[j] = t;
    }
    for (j = 0; j < NY; j++)
        for (i = 0; i < NX; i++) {
            uint32_t n = label[i + NX * j];
            points[2 * n] = 0.25 * (double)i + 0.01 * (double)(j * j);
            points[2 * n + 1] = 0.5 * (double)j;
            points32[2 * n] = (float)points[2 * n];
            points32[2 * n + 1] = (float)points[2 * n + 1];
            if (i + 1 < NX) { edges[e++] = n; edges[e++] = label[i + 1 + NX * j]; }
            if (j + 1 < NY) { edges[e++] = n; edges[e++] = label[i + NX * (j + 1)]; }
            if (i + 1 < NX && j + 1 < NY) { edges[e++] = n; edges[e++] = label[i + 1 + NX * (j + 1)]; }
        }
    OK(dk_graph_from_edges(N, edges, 2 * EDGES, 0, NULL, 0, offsets, N + 1, targets, 2 * EDGES, &used));
}

static void ints(const char *name, const uint32_t *v, size_t n) {
    size_t i;
    printf("%s", name);
    for (i = 0; i < n; i++) printf(" %lu", (unsigned long)v[i]);
    printf("\n");
}

static void keys_hex(const char *name, const uint64_t *v, size_t n) {
    size_t i;
    printf("%s", name);
    for (i = 0; i < n; i++) printf(" %016llX", (unsigned long long)v[i]);
    printf("\n");
}

int main(void) {
    static uint32_t order[N], inverse[N], horder[N], hinverse[N], o32[N], i32[N];
    static uint64_t keys[N], keys32[N];
    static uint32_t poff[N + 1], ptgt[2 * EDGES], map[2 * EDGES], boff[N + 1], btgt[2 * EDGES];
    static double stiff[2 * EDGES], pstiff[2 * EDGES], moved[2 * N], back[2 * N];
    static float moved32[2 * N], back32[2 * N], stiff32[2 * EDGES], pstiff32[2 * EDGES];
    static uint32_t cells[3 * N], cells0[3 * N];
    uint32_t bad_order[N], before[N], maxd;
    uint64_t sumd, before_keys[N];
    size_t i;
    dk_graph graph, permuted;
    dk_permutation perm, undo, none, broken;

    build();
    ints("edges", edges, 2 * EDGES);
    hex64("points", points, 2 * N);
    graph.offsets = offsets; graph.offsets_len = N + 1; graph.targets = targets; graph.targets_len = used;

    OK(dk_order_rcm(&graph, order, N, inverse, N));
    ints("rcm", order, N);
    OK(dk_order_hilbert(points, 2 * N, 2, horder, N, hinverse, N, keys, N));
    ints("hilbert_f64", horder, N);
    keys_hex("keys_f64", keys, N);
    OK(dk_order_hilbert_f32(points32, 2 * N, 2, o32, N, i32, N, keys32, N));
    ints("hilbert_f32", o32, N);
    keys_hex("keys_f32", keys32, N);

    perm.order = order; perm.order_len = N; perm.inverse = inverse; perm.inverse_len = N;
    undo.order = inverse; undo.order_len = N; undo.inverse = order; undo.inverse_len = N;
    memset(&none, 0, sizeof none);
    OK(dk_order_index_distance(&graph, &none, &maxd, &sumd));
    printf("distance %lu %llu\n", (unsigned long)maxd, (unsigned long long)sumd);
    OK(dk_order_index_distance(&graph, &perm, &maxd, &sumd));
    printf("distance_rcm %lu %llu\n", (unsigned long)maxd, (unsigned long long)sumd);

    /* Points (width 2) there and back, both precisions. */
    OK(dk_order_permute(&perm, 2, points, 2 * N, moved, 2 * N));
    hex64("moved", moved, 2 * N);
    OK(dk_order_permute(&undo, 2, moved, 2 * N, back, 2 * N));
    SAME(back, points, sizeof points);
    OK(dk_order_permute_f32(&perm, 2, points32, 2 * N, moved32, 2 * N));
    hex32("moved_f32", moved32, 2 * N);
    OK(dk_order_permute_f32(&undo, 2, moved32, 2 * N, back32, 2 * N));
    SAME(back32, points32, sizeof points32);
    /* Width 1 over 2N scalars is 2N nodes, not N. */
    EXPECT(dk_order_permute_f32(&perm, 1, points32, 2 * N, moved32, 2 * N), DK_ERR_LENGTH_MISMATCH);

    /* Cell node lists, 1-based, there and back. */
    for (i = 0; i < 3 * N; i++) cells[i] = cells0[i] = (uint32_t)((i * 7919) % N) + 1;
    OK(dk_order_renumber(&perm, 1, cells, 3 * N));
    for (i = 0; i < 3 * N; i++) CHECK(cells[i] == inverse[cells0[i] - 1] + 1);
    OK(dk_order_renumber(&undo, 1, cells, 3 * N));
    SAME(cells, cells0, sizeof cells);

    /* The graph and its per-edge data, there and back. */
    for (i = 0; i < used; i++) stiff[i] = 1.0 / (double)(i + 3);
    OK(dk_order_permute_graph(&perm, &graph, poff, N + 1, ptgt, used, map, used));
    ints("graph_offsets", poff, N + 1);
    ints("graph_targets", ptgt, used);
    ints("edge_map", map, used);
    OK(dk_order_gather(map, used, stiff, used, pstiff, used));
    hex64("stiffness", pstiff, used);
    for (i = 0; i < used; i++) stiff32[i] = (float)stiff[i];
    OK(dk_order_gather_f32(map, used, stiff32, used, pstiff32, used));
    hex32("stiffness_f32", pstiff32, used);
    memcpy(before, pstiff32, sizeof before);
    map[0] = (uint32_t)used; /* out of range: nothing written */
    EXPECT(dk_order_gather_f32(map, used, stiff32, used, pstiff32, used), DK_ERR_INDEX_OUT_OF_RANGE);
    SAME(before, pstiff32, sizeof before);
    permuted.offsets = poff; permuted.offsets_len = N + 1; permuted.targets = ptgt; permuted.targets_len = used;
    OK(dk_order_permute_graph(&undo, &permuted, boff, N + 1, btgt, used, NULL, 0));
    SAME(boff, offsets, sizeof offsets);
    SAME(btgt, targets, used * sizeof *targets);

    /* Bad input: nothing written. */
    memcpy(bad_order, order, sizeof order);
    bad_order[1] = bad_order[0];
    broken = perm; broken.order = bad_order;
    memcpy(before, moved, sizeof before);
    EXPECT(dk_order_permute(&broken, 2, points, 2 * N, moved, 2 * N), DK_ERR_INVALID_PARAMETER);
    SAME(before, moved, sizeof before);
    EXPECT(dk_order_permute(&perm, 0, points, 2 * N, moved, 2 * N), DK_ERR_INVALID_PARAMETER);
    EXPECT(dk_order_permute(&perm, 2, points, 2 * N - 2, moved, 2 * N), DK_ERR_LENGTH_MISMATCH);
    SAME(before, moved, sizeof before);
    memcpy(before, horder, sizeof before);
    memcpy(before_keys, keys, sizeof before_keys);
    EXPECT(dk_order_hilbert(points, 2 * N, 2, horder, N, hinverse, N, keys, N - 1), DK_ERR_BUFFER_TOO_SMALL);
    EXPECT(dk_order_hilbert(points, 2 * N, 4, horder, N, hinverse, N, keys, N), DK_ERR_INVALID_PARAMETER);
    SAME(before, horder, sizeof before);
    SAME(before_keys, keys, sizeof before_keys);
    cells[5] = N + 1;
    memcpy(cells0, cells, sizeof cells);
    EXPECT(dk_order_renumber(&perm, 1, cells, 3 * N), DK_ERR_INDEX_OUT_OF_RANGE);
    EXPECT(dk_order_renumber(&perm, 2, cells, 3 * N), DK_ERR_BAD_INDEX_BASE);
    EXPECT(dk_order_renumber(&none, 0, cells, 3 * N), DK_ERR_NULL_POINTER);
    SAME(cells, cells0, sizeof cells);
    memcpy(before, order, sizeof before);
    EXPECT(dk_order_rcm(&graph, order, N - 1, inverse, N), DK_ERR_LENGTH_MISMATCH);
    EXPECT(dk_order_rcm(NULL, order, N, inverse, N), DK_ERR_NULL_POINTER);
    SAME(before, order, sizeof before);

    if (failures) return 1;
    printf("order: every check held\n");
    return 0;
}

/* The checks the C tests share: each failed check prints its line and counts in `failures`
 * (a test's main returns 1 when it is not 0), and the bit printers the host tests compare
 * with the Rust API's results. Included by solvers.c, solvers_amg.c, slide.c and (the
 * printers only) solvers_parity.c. */
#ifndef DEFORM_KERNEL_TEST_CHECK_H
#define DEFORM_KERNEL_TEST_CHECK_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deform_kernel.h"

#ifndef DK_TEST_PRINTERS_ONLY
static int failures = 0;

/* A call that must return `status`. */
#define EXPECT(call, status)                                                              \
    do {                                                                                  \
        dk_status s_ = (call);                                                            \
        if (s_ != (status)) {                                                             \
            printf("FAIL line %d: %s: got %d (%s), expected %d\n", __LINE__, #call,       \
                   (int)s_, dk_status_str((int32_t)s_), (int)(status));                   \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

#define OK(call) EXPECT(call, DK_OK)

#define CHECK(cond)                                                                       \
    do {                                                                                  \
        if (!(cond)) {                                                                    \
            printf("FAIL line %d: %s\n", __LINE__, #cond);                                \
            failures++;                                                                   \
        }                                                                                 \
    } while (0)

/* Bit-for-bit comparison of two objects of the same size. */
#define SAME(a, b, size) CHECK(memcmp((a), (b), (size)) == 0)

/* A structure filled with a byte pattern (so "untouched" is visible in every byte). */
#define POISON(obj) memset(&(obj), 0xA5, sizeof(obj))
#endif

/* malloc that never returns NULL (exit 2 when memory is out). */
static inline void *xmalloc(size_t bytes) {
    void *p = malloc(bytes ? bytes : 1);
    if (!p) {
        printf("out of memory\n");
        exit(2);
    }
    return p;
}

/* `label[0..n)` = a random permutation of 0..n (Fisher–Yates on an LCG from `seed`). */
static inline void lcg_shuffle(uint32_t *label, size_t n, uint64_t seed) {
    size_t i, j;
    for (i = 0; i < n; i++) label[i] = (uint32_t)i;
    for (i = n; i-- > 1;) {
        uint32_t t;
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        j = (size_t)((seed >> 33) % (i + 1));
        t = label[i];
        label[i] = label[j];
        label[j] = t;
    }
}

/* `name` and the bits of `v[0..n)`, as the host tests print them from Rust. */
static inline void hex64(const char *name, const double *v, size_t n) {
    size_t i;
    printf("%s", name);
    for (i = 0; i < n; i++) {
        uint64_t b;
        memcpy(&b, &v[i], sizeof b);
        printf(" %016llX", (unsigned long long)b);
    }
    printf("\n");
}

static inline void hex32(const char *name, const float *v, size_t n) {
    size_t i;
    printf("%s", name);
    for (i = 0; i < n; i++) {
        uint32_t b;
        memcpy(&b, &v[i], sizeof b);
        printf(" %08lX", (unsigned long)b);
    }
    printf("\n");
}

#endif

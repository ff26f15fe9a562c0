/* deform_kernel_mpi: dk_exchange callbacks over MPI (see deform_kernel_mpi.h). */
#include "deform_kernel_mpi.h"

#include <limits.h>
#include <stdlib.h>

/* The tag of the kernel's halo messages (on the duplicated communicator). */
enum { DK_MPI_TAG = 0x6b64 };

typedef struct {
    MPI_Comm comm;
} dk_mpi_context;

static MPI_Comm comm_of(void *user) { return ((dk_mpi_context *)user)->comm; }

static int32_t sum_words(void *user, int64_t *words, size_t len) {
    if (len > INT_MAX) return -1;
    return MPI_Allreduce(MPI_IN_PLACE, words, (int)len, MPI_INT64_T, MPI_SUM, comm_of(user));
}

static int32_t max_values(void *user, double *values, size_t len) {
    if (len > INT_MAX) return -1;
    return MPI_Allreduce(MPI_IN_PLACE, values, (int)len, MPI_DOUBLE, MPI_MAX, comm_of(user));
}

/* Copies `width` doubles per listed node between the field and a packed buffer; an index
 * past the field (never after the kernel's checks) is skipped and counted. */
static size_t pack(const uint32_t *nodes, size_t count, double *field, size_t field_len,
                   double *buffer, size_t width, int unpack) {
    size_t bad = 0;
    for (size_t q = 0; q < count; q++) {
        size_t at = (size_t)nodes[q] * width;
        if (at + width > field_len) {
            bad++;
            continue;
        }
        for (size_t c = 0; c < width; c++) {
            if (unpack)
                field[at + c] = buffer[q * width + c];
            else
                buffer[q * width + c] = field[at + c];
        }
    }
    return bad;
}

/* One nonblocking send and receive per neighbour, then MPI_Waitall. Every message is posted
 * even when a count does not fit, so no peer is left waiting. */
static int32_t halo(void *user, const dk_partition *p, double *field, size_t field_len,
                    size_t width) {
    MPI_Comm comm = comm_of(user);
    size_t nb = p->neighbour_ranks_len;
    double *send = malloc((p->send_len * width + 1) * sizeof *send);
    double *recv = malloc((p->recv_len * width + 1) * sizeof *recv);
    MPI_Request *req = malloc((2 * nb + 1) * sizeof *req);
    if (!send || !recv || !req) {
        free(send), free(recv), free(req);
        return -1;
    }
    size_t bad = pack(p->send, p->send_len, field, field_len, send, width, 0);
    int status = MPI_SUCCESS;
    for (size_t k = 0; k < nb; k++) {
        size_t r0 = p->recv_offsets[k], r1 = p->recv_offsets[k + 1];
        size_t s0 = p->send_offsets[k], s1 = p->send_offsets[k + 1];
        int rank = (int)p->neighbour_ranks[k];
        int rc = MPI_Irecv(recv + r0 * width, (int)((r1 - r0) * width), MPI_DOUBLE, rank,
                           DK_MPI_TAG, comm, &req[2 * k]);
        int sc = MPI_Isend(send + s0 * width, (int)((s1 - s0) * width), MPI_DOUBLE, rank,
                           DK_MPI_TAG, comm, &req[2 * k + 1]);
        if (rc != MPI_SUCCESS) status = rc, req[2 * k] = MPI_REQUEST_NULL;
        if (sc != MPI_SUCCESS) status = sc, req[2 * k + 1] = MPI_REQUEST_NULL;
    }
    int wc = MPI_Waitall((int)(2 * nb), req, MPI_STATUSES_IGNORE);
    if (wc != MPI_SUCCESS) status = wc;
    bad += pack(p->recv, p->recv_len, field, field_len, recv, width, 1);
    free(send), free(recv), free(req);
    if (status == MPI_SUCCESS && bad) status = -1;
    return status;
}

int dk_mpi_exchange_new(MPI_Comm comm, dk_exchange *ex) {
    dk_mpi_context *ctx = malloc(sizeof *ctx);
    if (!ctx) return -1;
    int rc = MPI_Comm_dup(comm, &ctx->comm);
    if (rc != MPI_SUCCESS) {
        free(ctx);
        return rc;
    }
    MPI_Comm_set_errhandler(ctx->comm, MPI_ERRORS_RETURN);
    ex->user = ctx;
    ex->sum_words = sum_words;
    ex->max = max_values;
    ex->halo = halo;
    return MPI_SUCCESS;
}

int dk_mpi_exchange_new_f(MPI_Fint comm, dk_exchange *ex) {
    return dk_mpi_exchange_new(MPI_Comm_f2c(comm), ex);
}

void dk_mpi_exchange_free(dk_exchange *ex) {
    if (!ex || !ex->user) return;
    dk_mpi_context *ctx = ex->user;
    MPI_Comm_free(&ctx->comm);
    free(ctx);
    ex->user = NULL;
    ex->sum_words = NULL;
    ex->max = NULL;
    ex->halo = NULL;
}

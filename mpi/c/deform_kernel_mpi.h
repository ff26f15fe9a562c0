/*
 * deform_kernel_mpi: the exchange callbacks of deform-kernel's distributed calls
 * (dk_exchange, see deform_kernel.h and ffi/src/partition.rs) over an MPI communicator.
 *
 *   dk_exchange ex;
 *   dk_mpi_exchange_new(MPI_COMM_WORLD, &ex);          (collective)
 *   dk_partitioned_spring_solve(..., &ex, &report);    (collective, as often as needed)
 *   dk_mpi_exchange_free(&ex);                          (collective)
 *
 * Sums of int64_t words and maxima of doubles are MPI_Allreduce calls; the halo exchange is
 * one MPI_Isend and one MPI_Irecv per neighbour of the partition, then MPI_Waitall: only
 * the ghosts travel. The communicator is duplicated (the kernel's messages never meet the
 * caller's) with MPI_ERRORS_RETURN, so a failing MPI call makes its callback return nonzero
 * and the kernel reports DK_ERR_EXCHANGE on every process instead of aborting the job.
 *
 * Compile deform_kernel_mpi.c with mpicc next to the caller's code (no other dependency
 * than MPI and deform_kernel.h); Fortran passes its communicator to dk_mpi_exchange_new_f.
 */
#ifndef DEFORM_KERNEL_MPI_H
#define DEFORM_KERNEL_MPI_H

#include <mpi.h>

#include "deform_kernel.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fills *ex with the callbacks over a duplicate of comm (its user pointer owns the
 * duplicate). Collective over comm. Returns MPI_SUCCESS, an MPI error code, or -1 when
 * memory runs out (then *ex is untouched). */
int dk_mpi_exchange_new(MPI_Comm comm, dk_exchange *ex);

/* dk_mpi_exchange_new for a Fortran communicator handle (MPI_Comm_f2c). */
int dk_mpi_exchange_new_f(MPI_Fint comm, dk_exchange *ex);

/* Frees the duplicate communicator (collective) and clears *ex. */
void dk_mpi_exchange_free(dk_exchange *ex);

#ifdef __cplusplus
}
#endif

#endif

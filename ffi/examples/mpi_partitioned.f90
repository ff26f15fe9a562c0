! The Fortran twin of mpi_partitioned.c: each rank holds only its columns of the grid, one ghost
! column on each side and the triangles around them, solves the linear springs through
! dk_partitioned_spring_solve with the MPI callbacks of mpi/c/deform_kernel_mpi.c (from a
! Fortran communicator: dk_mpi_exchange_new_f), and the owned values, gathered on rank 0 by
! global id, equal the serial dk_spring_solve_linear bit for bit (issue 27). Then the same
! view moves the mesh with the quaternion deformation (dk_partitioned_deform_spring): the owned
! fixed nodes with their positions in the global boundary list (the fixed nodes by global id,
! counted from the grid's formulas), their deformed points and one rigid rotation (the plate's
! pitch); the gathered owned points, the origin and the report equal the serial
! dk_deform_spring (through dkf_deform_spring) bit for bit.
!
!   mpicc -c -Iffi/generated -Impi/c mpi/c/deform_kernel_mpi.c
!   mpif90 ffi/generated/deform_kernel.f90 ffi/examples/mpi_partitioned.f90 \
!          deform_kernel_mpi.o libdeform_kernel.a -lm -lpthread -ldl
!   mpirun -np 4 ./a.out
!
! The partition struct takes 0-based local node numbers (c_loc of the arrays).
program mpi_partitioned
  use, intrinsic :: iso_c_binding
  use mpi
  use deform_kernel
  implicit none

  interface
    function dk_mpi_exchange_new_f(comm, ex) bind(C, name="dk_mpi_exchange_new_f") result(s)
      import :: c_int, dk_exchange
      integer(c_int), value :: comm
      type(dk_exchange), intent(inout) :: ex
      integer(c_int) :: s
    end function
    subroutine dk_mpi_exchange_free(ex) bind(C, name="dk_mpi_exchange_free")
      import :: dk_exchange
      type(dk_exchange), intent(inout) :: ex
    end subroutine
  end interface

  integer, parameter :: NX = 61, NY = 41, PLATE0 = 20, PLATE1 = 32, V = 2, MIDROW = 20
  integer :: rank, nranks, ierr, c0, c1, nb, nloc, nown, i, j, l, ok, all_ok
  integer :: ncells, q0, q1
  integer(c_int64_t), allocatable, target :: ids(:)
  real(c_double), allocatable, target :: pts(:), x(:), scratch(:), want(:, :)
  integer(c_int8_t), allocatable, target :: fixed(:), kinds(:)
  integer(c_int32_t), allocatable, target :: send(:), recv(:), coff(:), cnodes(:), iscratch(:)
  integer(c_int32_t), target :: ranks(2), soff(3), roff(3)
  type(dk_partition) :: part
  type(dk_cells) :: cells
  type(dk_exchange) :: ex
  type(dk_spring_solve_options) :: opts
  type(dk_spring_solve_report) :: rep, srep, qrep, qsrep
  integer(c_size_t) :: sl, il
  real(c_double), allocatable :: qwant(:, :)
  real(c_double) :: qorigin(2), qsorigin(2)

  call MPI_Init(ierr)
  call MPI_Comm_rank(MPI_COMM_WORLD, rank, ierr)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks, ierr)
  call check(dk_mpi_exchange_new_f(int(MPI_COMM_WORLD, c_int), ex), "dk_mpi_exchange_new_f")

  ! Owned columns c0 .. c1 - 1, ghost columns c0 - 1 and c1 where they exist.
  c0 = 0
  do while (owner(c0) < rank)
    c0 = c0 + 1
  end do
  c1 = c0
  do while (c1 < NX)
    if (owner(c1) /= rank) exit
    c1 = c1 + 1
  end do
  nown = (c1 - c0) * NY
  nloc = nown + (merge(1, 0, c0 > 0) + merge(1, 0, c1 < NX)) * NY
  allocate(ids(0:nloc - 1), pts(0:2 * nloc - 1), fixed(0:nloc - 1), x(0:V * nloc - 1))
  do i = max(c0 - 1, 0), min(c1, NX - 1)
    do j = 0, NY - 1
      l = local_of(i, j)
      ids(l) = int(j, c_int64_t) * NX + i
      call point(i, j, pts(2 * l:2 * l + 1))
      fixed(l) = merge(1_c_int8_t, 0_c_int8_t, fixed_at(i, j))
      x(V * l:V * l + 1) = 1d300
      if (l < nown) call prescribed(i, j, x(V * l:V * l + 1))
    end do
  end do

  ! Neighbours (left, then right): send my edge column, receive theirs (j ascending).
  allocate(send(0:2 * NY - 1), recv(0:2 * NY - 1))
  nb = 0
  soff(1) = 0
  roff(1) = 0
  if (c0 > 0) call neighbour(owner(c0 - 1), c0, c0 - 1)
  if (c1 < NX) call neighbour(owner(c1), c1 - 1, c1)

  ! Cells: both triangles of every quad (columns q, q + 1) touching an owned column.
  q0 = max(c0 - 1, 0)
  q1 = min(c1, NX - 1)
  ncells = (q1 - q0) * (NY - 1) * 2
  allocate(coff(0:ncells), cnodes(0:3 * ncells - 1), kinds(0:ncells - 1))
  l = 0
  do i = q0, q1 - 1
    do j = 0, NY - 2
      cnodes(3 * l:3 * l + 5) = [local_of(i, j), local_of(i + 1, j), local_of(i + 1, j + 1), &
                                 local_of(i, j), local_of(i + 1, j + 1), local_of(i, j + 1)]
      l = l + 2
    end do
  end do
  coff = [(3 * l, l = 0, ncells)]
  kinds = 5_c_int8_t

  part = dk_partition(int(rank, c_int32_t), int(nranks, c_int32_t), int(nown, c_size_t), &
                      int(NX, c_int64_t) * NY, c_loc(ids), int(nloc, c_size_t), c_loc(ranks), &
                      int(nb, c_size_t), c_loc(soff), int(nb + 1, c_size_t), c_loc(send), &
                      int(soff(nb + 1), c_size_t), c_loc(roff), int(nb + 1, c_size_t), &
                      c_loc(recv), int(roff(nb + 1), c_size_t))
  cells = dk_cells(c_loc(coff), size(coff, kind=c_size_t), c_loc(cnodes), &
                   size(cnodes, kind=c_size_t), c_loc(kinds), size(kinds, kind=c_size_t))
  call check(dk_spring_solve_options_default(opts), "options")
  call check(dk_partitioned_spring_scratch_len(part, cells, .false._c_bool, int(V, c_int32_t), &
                                               sl, il), "scratch_len")
  allocate(scratch(sl), iscratch(il))
  call check(dk_partitioned_spring_solve(part, cells, .false._c_bool, pts, size(pts, kind=c_size_t), &
                                         2_c_int32_t, 1d0, fixed, size(fixed, kind=c_size_t), opts, &
                                         int(V, c_int32_t), x, size(x, kind=c_size_t), scratch, sl, &
                                         iscratch, il, ex, rep), "dk_partitioned_spring_solve")

  call serial(want, srep, qwant, qsorigin, qsrep)
  ok = merge(1, 0, rep%iterations == srep%iterations .and. &
                   transfer(rep%residual, 0_c_int64_t) == transfer(srep%residual, 0_c_int64_t))
  ok = min(ok, gathered_equal())
  call MPI_Allreduce(ok, all_ok, 1, MPI_INTEGER, MPI_MIN, MPI_COMM_WORLD, ierr)
  if (rank == 0) write (*, '(a, i0, a, i0, a, a)') 'mpi_partitioned.f90: ', nranks, &
      ' rank(s), ', rep%iterations, ' CG iterations: assembled field ', &
      merge('bit-identical to the serial solve', 'DIFFERS from the serial solve    ', all_ok == 1)

  ! The quaternion deformation on the same view, its owned points compared as the values were.
  call deform_quaternion(x, qorigin, qrep)
  want = qwant
  ok = merge(1, 0, qrep%iterations == qsrep%iterations .and. &
                   transfer(qrep%residual, 0_c_int64_t) == transfer(qsrep%residual, 0_c_int64_t) &
                   .and. all(transfer(qorigin, 0_c_int64_t, 2) == transfer(qsorigin, 0_c_int64_t, 2)))
  ok = min(ok, gathered_equal())
  call MPI_Allreduce(ok, i, 1, MPI_INTEGER, MPI_MIN, MPI_COMM_WORLD, ierr)
  if (rank == 0) write (*, '(a, i0, a, i0, a, a)') 'mpi_partitioned.f90: quaternion deformation, ', &
      nranks, ' rank(s), ', qrep%iterations, ' CG iterations: owned points, origin and report ', &
      merge('bit-identical to the serial dk_deform_spring', 'DIFFER from the serial dk_deform_spring     ', &
            i == 1)
  all_ok = min(all_ok, i)
  call dk_mpi_exchange_free(ex)
  call MPI_Finalize(ierr)
  if (all_ok /= 1) error stop 1

contains

  integer function owner(i)
    integer, intent(in) :: i
    owner = int(int(i, 8) * nranks / NX)
  end function

  integer(c_int32_t) function local_of(i, j)
    integer, intent(in) :: i, j
    if (i >= c0 .and. i < c1) then
      local_of = (i - c0) * NY + j
    else if (i == c0 - 1) then
      local_of = nown + j
    else
      local_of = nown + merge(NY, 0, c0 > 0) + j
    end if
  end function

  subroutine neighbour(r, mine, theirs)
    integer, intent(in) :: r, mine, theirs
    integer :: jj
    nb = nb + 1
    ranks(nb) = r
    do jj = 0, NY - 1
      send(soff(nb) + jj) = local_of(mine, jj)
      recv(roff(nb) + jj) = local_of(theirs, jj)
    end do
    soff(nb + 1) = soff(nb) + NY
    roff(nb + 1) = roff(nb) + NY
  end subroutine

  subroutine point(i, j, p)
    integer, intent(in) :: i, j
    real(c_double), intent(out) :: p(2)
    real(c_double) :: s, t
    s = real(i, c_double) / (NX - 1)
    t = real(j, c_double) / (NY - 1)
    p = [-2d0 + 4d0 * s + 0.05d0 * sin(6d0 * t), -1.5d0 + 3d0 * t]
  end subroutine

  logical function on_plate(i, j)
    integer, intent(in) :: i, j
    on_plate = j == MIDROW .and. i >= PLATE0 .and. i <= PLATE1
  end function

  logical function fixed_at(i, j)
    integer, intent(in) :: i, j
    fixed_at = i == 0 .or. j == 0 .or. i == NX - 1 .or. j == NY - 1 .or. on_plate(i, j)
  end function

  ! The plate pitched by 8 degrees about its quarter chord; 0 elsewhere.
  subroutine prescribed(i, j, d)
    integer, intent(in) :: i, j
    real(c_double), intent(out) :: d(2)
    real(c_double) :: a(2), b(2), p(2), cx, cy, th
    d = 0
    if (.not. on_plate(i, j)) return
    call point(PLATE0, MIDROW, a)
    call point(PLATE1, MIDROW, b)
    call point(i, j, p)
    cx = a(1) + 0.25d0 * (b(1) - a(1))
    cy = a(2)
    th = -8d0 * 3.14159265358979323846d0 / 180d0
    d = [cos(th) * (p(1) - cx) - sin(th) * (p(2) - cy) + cx - p(1), &
         sin(th) * (p(1) - cx) + cos(th) * (p(2) - cy) + cy - p(2)]
  end subroutine

  ! The whole mesh on one process (1-based cells through the dkf_ wrappers).
  subroutine serial(w, r, qw, qo, qr)
    real(c_double), allocatable, intent(out) :: w(:, :), qw(:, :)
    real(c_double), intent(out) :: qo(2)
    type(dk_spring_solve_report), intent(out) :: r, qr
    integer(c_int32_t), allocatable, target :: off(:), nodes(:), goff(:), targets(:), isc(:)
    integer(c_int8_t), allocatable, target :: kk(:), fx(:)
    real(c_double), allocatable, target :: p(:, :), k(:), sc(:)
    integer(c_size_t) :: n, nc, tl, used, scl
    integer :: ii, jj, c
    n = int(NX, c_size_t) * NY
    nc = int(NX - 1, c_size_t) * (NY - 1) * 2
    allocate(off(nc + 1), nodes(3 * nc), kk(nc), fx(n), p(2, n), w(V, n), goff(n + 1), isc(n))
    c = 0
    do ii = 0, NX - 2
      do jj = 0, NY - 2
        nodes(3 * c + 1:3 * c + 6) = 1 + [g(ii, jj), g(ii + 1, jj), g(ii + 1, jj + 1), &
                                          g(ii, jj), g(ii + 1, jj + 1), g(ii, jj + 1)]
        c = c + 2
      end do
    end do
    off = [(3 * c + 1, c = 0, int(nc))]
    kk = 5_c_int8_t
    do jj = 0, NY - 1
      do ii = 0, NX - 1
        call point(ii, jj, p(:, g(ii, jj) + 1))
        fx(g(ii, jj) + 1) = merge(1_c_int8_t, 0_c_int8_t, fixed_at(ii, jj))
        call prescribed(ii, jj, w(:, g(ii, jj) + 1))
      end do
    end do
    call check(dkf_graph_from_cells_len(n, off, nodes, kk, .false., tl), "graph len")
    allocate(targets(tl))
    call check(dkf_graph_from_cells(n, off, nodes, kk, .false., goff, targets, used), "graph")
    allocate(k(used))
    call check(dk_spring_batina_stiffness(dkf_graph(goff, targets(1:used)), p, size(p, kind=c_size_t), &
                                          2_c_int32_t, 1d0, k, used), "stiffness")
    call check(dk_spring_solve_linear_scratch_len(n, int(V, c_int32_t), opts, scl), "scratch")
    allocate(sc(scl))
    call check(dkf_spring_solve_linear(goff, targets(1:used), k, fx, opts, w, sc, isc, r), "serial")
    call serial_deform(p, fx, goff, targets(1:used), k, qw, qo, qr)
  end subroutine

  ! The serial quaternion deformation of the whole mesh: the fixed nodes by global id
  ! (1-based), the plate's rigid pitch.
  subroutine serial_deform(p, fx, goff, targets, k, qw, qo, qr)
    real(c_double), intent(in) :: p(:, :), k(:)
    integer(c_int8_t), intent(in) :: fx(:)
    integer(c_int32_t), intent(in) :: goff(:), targets(:)
    real(c_double), allocatable, intent(out) :: qw(:, :)
    real(c_double), intent(out) :: qo(2)
    type(dk_spring_solve_report), intent(out) :: qr
    integer(c_int32_t), allocatable :: bn(:), isc(:)
    real(c_double), allocatable :: bd(:, :), sc(:), vals(:), tr(:, :), rot(:, :)
    real(c_double) :: q(4), o(3), u(2)
    integer(c_size_t) :: n, nbs, scl, vl
    integer :: ii, jj, c
    n = size(fx, kind=c_size_t)
    nbs = count(fx /= 0)
    allocate(bn(nbs), bd(2, nbs), qw(2, n), tr(2, n), rot(4, n), isc(n + nbs))
    c = 0
    do jj = 0, NY - 1
      do ii = 0, NX - 1
        if (.not. fixed_at(ii, jj)) cycle
        c = c + 1
        bn(c) = g(ii, jj) + 1
        call prescribed(ii, jj, u)
        bd(:, c) = p(:, g(ii, jj) + 1) + u
      end do
    end do
    call pitch(q, o)
    call check(dk_deform_spring_scratch_len(n, nbs, 2_c_int32_t, opts, scl, vl), "deform lens")
    allocate(sc(scl), vals(vl))
    call check(dkf_deform_spring(p, bn, bd, goff, targets, k, fx, opts, sc, vals, isc, tr, rot, &
                                 qw, qr, rigid_rotation=q, origin=o(1:2), origin_out=qo), &
               "serial deform")
  end subroutine

  ! The plate's pitch about its quarter chord: quaternion (w, x, y, z) and origin.
  subroutine pitch(q, o)
    real(c_double), intent(out) :: q(4), o(3)
    real(c_double) :: a(2), b(2), th
    call point(PLATE0, MIDROW, a)
    call point(PLATE1, MIDROW, b)
    th = -8d0 * 3.14159265358979323846d0 / 180d0
    q = [cos(th / 2), 0d0, 0d0, sin(th / 2)]
    o = [a(1) + 0.25d0 * (b(1) - a(1)), a(2), 0d0]
  end subroutine

  ! Position of fixed node (i, j) in the global boundary list: the fixed nodes with a smaller
  ! global id, from the grid's formulas.
  integer(c_int32_t) function bpos(i, j)
    integer, intent(in) :: i, j
    integer :: r, c
    bpos = 0
    do r = 0, j - 1
      if (r == 0 .or. r == NY - 1) then
        bpos = bpos + NX
      else
        bpos = bpos + 2 + merge(PLATE1 - PLATE0 + 1, 0, r == MIDROW)
      end if
    end do
    do c = 0, i - 1
      if (fixed_at(c, j)) bpos = bpos + 1
    end do
  end function

  ! The partitioned quaternion deformation of this rank's view into xo(0:2 nown - 1).
  subroutine deform_quaternion(xo, qo, qr)
    real(c_double), intent(inout) :: xo(0:)
    real(c_double), intent(out) :: qo(2)
    type(dk_spring_solve_report), intent(out) :: qr
    integer(c_int32_t), allocatable, target :: bn(:), bp(:), isc(:)
    real(c_double), allocatable, target :: bd(:), sc(:)
    integer(c_int64_t), allocatable :: words(:)
    integer(c_int8_t), allocatable :: kk(:)
    real(c_double) :: q(4), o(3), p(2), u(2)
    integer(c_size_t) :: lens(4)
    type(dk_partitioned_motion) :: m
    integer :: nbn, ll, ii, jj
    nbn = count(fixed(0:nown - 1) /= 0)
    allocate(bn(0:max(nbn, 1) - 1), bp(0:max(nbn, 1) - 1), bd(0:2 * max(nbn, 1) - 1))
    nbn = 0
    do ll = 0, nown - 1
      if (fixed(ll) == 0) cycle
      ii = int(mod(ids(ll), int(NX, c_int64_t)))
      jj = int(ids(ll) / NX)
      call point(ii, jj, p)
      call prescribed(ii, jj, u)
      bn(nbn) = ll
      bp(nbn) = bpos(ii, jj)
      bd(2 * nbn:2 * nbn + 1) = p + u
      nbn = nbn + 1
    end do
    call pitch(q, o)
    m = dk_partitioned_motion(c_loc(bn), int(nbn, c_size_t), c_loc(bp), int(nbn, c_size_t), &
                              c_loc(bd), int(2 * nbn, c_size_t), &
                              int(bpos(NX - 1, NY - 1) + 1, c_size_t), c_null_ptr, 0_c_size_t, &
                              dk_cells(c_null_ptr, 0_c_size_t, c_null_ptr, 0_c_size_t, &
                                       c_null_ptr, 0_c_size_t), &
                              0_c_size_t, q, o, DK_ROTATIONS_RIGID, 1_c_int32_t)
    call check(dk_partitioned_deform_spring_lens(part, cells, .false._c_bool, 2_c_int32_t, &
                                                 m%boundary_count, 0_c_size_t, lens), "lens")
    allocate(sc(lens(1)), isc(lens(2)), words(lens(3)), kk(max(lens(4), 1_c_size_t)))
    call check(dk_partitioned_deform_spring(part, cells, .false._c_bool, pts, &
                                            size(pts, kind=c_size_t), 2_c_int32_t, 1d0, fixed, &
                                            size(fixed, kind=c_size_t), m, opts, sc, lens(1), &
                                            isc, lens(2), words, lens(3), kk, lens(4), ex, xo, &
                                            int(2 * nown, c_size_t), qo, 2_c_size_t, qr), &
               "dk_partitioned_deform_spring")
  end subroutine

  integer(c_int32_t) function g(ii, jj)
    integer, intent(in) :: ii, jj
    g = jj * NX + ii
  end function

  ! 1 on every rank when the owned values, gathered on rank 0 by global id, cover every node
  ! once and equal the serial field bit for bit.
  integer function gathered_equal()
    integer :: counts(0:nranks - 1), displs(0:nranks - 1), r, n
    integer(c_int64_t), allocatable :: gids(:)
    real(c_double), allocatable :: vals(:), field(:, :)
    logical, allocatable :: seen(:)
    call MPI_Gather(nown, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, 0, MPI_COMM_WORLD, ierr)
    displs = 0
    do r = 1, nranks - 1
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
    n = sum(counts)
    allocate(gids(max(n, 1)), vals(max(V * n, 1)))
    call MPI_Gatherv(ids, nown, MPI_INTEGER8, gids, counts, displs, MPI_INTEGER8, 0, &
                     MPI_COMM_WORLD, ierr)
    call MPI_Gatherv(x, V * nown, MPI_DOUBLE_PRECISION, vals, V * counts, V * displs, &
                     MPI_DOUBLE_PRECISION, 0, MPI_COMM_WORLD, ierr)
    gathered_equal = 1
    if (rank == 0) then
      allocate(field(V, NX * NY), seen(NX * NY))
      seen = .false.
      do r = 1, n
        if (seen(gids(r) + 1)) gathered_equal = 0
        seen(gids(r) + 1) = .true.
        field(:, gids(r) + 1) = vals(V * r - 1:V * r)
      end do
      if (n /= NX * NY .or. .not. all(seen)) gathered_equal = 0
      if (any(transfer(field, 0_c_int64_t, V * n) /= transfer(want, 0_c_int64_t, V * n))) &
        gathered_equal = 0
    end if
    call MPI_Bcast(gathered_equal, 1, MPI_INTEGER, 0, MPI_COMM_WORLD, ierr)
  end function

  subroutine check(s, what)
    integer(c_int32_t), intent(in) :: s
    character(*), intent(in) :: what
    integer :: e
    if (s /= DK_OK) then
      write (*, '(a, a, i0)') what, ' failed: status ', s
      call MPI_Abort(MPI_COMM_WORLD, 2, e)
    end if
  end subroutine

end program

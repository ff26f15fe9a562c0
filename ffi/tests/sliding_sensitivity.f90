! The sliding springs' sensitivities from Fortran through the generated interfaces
! (dk_sensitivity_spring_sliding_tangent, dk_sensitivity_spring_sliding_adjoint_scratch_len,
! dk_sensitivity_spring_sliding_adjoint) on a 5 x 4 node grid (one diagonal per cell, Batina's
! stiffness) whose bottom edge slides along x and whose other boundary nodes are fixed: the
! dot-product identity <J v, w> = <v, J^T w> to 1e-12 relative, the tangent in the sliding
! line (y exactly 0) and the adjoint zero off the fixed nodes; a method other than CG is
! refused with g untouched. Prints "sliding_sensitivity: every check held" when every check
! holds.
program sliding_sensitivity
  use, intrinsic :: iso_c_binding, only: c_double, c_int32_t, c_int8_t, c_size_t
  use deform_kernel
  implicit none

  integer, parameter :: NX = 5, NY = 4, N = NX * NY
  integer, parameter :: M = (NX - 1) * NY + NX * (NY - 1) + (NX - 1) * (NY - 1)
  integer(c_int32_t) :: edges(2, M)
  integer(c_int32_t), target :: offsets(N + 1), targets(2 * M)
  real(c_double), target :: stiffness(2 * M), points(2, N), directions(2, N)
  integer(c_int8_t), target :: kinds(N), mask(N)
  real(c_double) :: v(2, N), w(2, N), jv(2, N), g(2, N), before(2, N), rel
  real(c_double), allocatable :: scratch(:), tangent_scratch(:)
  integer(c_int32_t) :: index_scratch(N)
  integer(c_size_t) :: used, len, tlen
  type(dk_spring_solve_options) :: options
  type(dk_spring_solve_report) :: report
  type(dk_spring_system) :: sys
  type(dk_constraints) :: con
  integer :: i, j, k, e, failures

  failures = 0
  e = 0
  do j = 1, NY
    do i = 1, NX
      k = i + NX * (j - 1)
      points(:, k) = [real(i - 1, c_double) + 0.1_c_double * sin(real(k, c_double)), &
                      real(j - 1, c_double) * 0.8_c_double]
      directions(:, k) = 0
      if (j == 1 .and. i > 1 .and. i < NX) then
        kinds(k) = 2
        directions(:, k) = [0, 1]
      else if (i == 1 .or. i == NX .or. j == 1 .or. j == NY) then
        kinds(k) = 1
      else
        kinds(k) = 0
      end if
      mask(k) = merge(1_c_int8_t, 0_c_int8_t, kinds(k) == 1)
      v(:, k) = 0
      if (kinds(k) == 1) v(:, k) = [sin(1.7_c_double * k), cos(0.9_c_double * k)]
      w(:, k) = [cos(2.3_c_double * k), sin(0.4_c_double * k + 1)]
      if (i < NX) call edge(k, k + 1)
      if (j < NY) call edge(k, k + NX)
      if (i < NX .and. j < NY) call edge(k, k + NX + 1)
    end do
  end do
  call expect(e == M, 'edge count')
  call expect(dkf_graph_from_edges(int(N, c_size_t), edges, offsets, targets, used) == DK_OK, &
              'graph status')
  call expect(dk_spring_batina_stiffness(dkf_graph(offsets, targets), points, &
                                         size(points, kind=c_size_t), 2_c_int32_t, &
                                         1.0_c_double, stiffness, &
                                         size(stiffness, kind=c_size_t)) == DK_OK, 'stiffness')
  sys = dkf_spring_system(dkf_graph(offsets, targets), stiffness, mask)
  con = dkf_constraints(kinds, directions)
  call expect(dk_spring_solve_options_default(options) == DK_OK, 'options')
  options%residual_tol = 1e-13_c_double

  ! The tangent (the sliding solve with v as Dirichlet data) and the adjoint of w.
  call expect(dk_spring_solve_linear_sliding_scratch_len(int(N, c_size_t), 2_c_int32_t, &
                                                         options, tlen) == DK_OK, &
              'tangent scratch length')
  call expect(dk_sensitivity_spring_sliding_adjoint_scratch_len(int(N, c_size_t), &
                                                                2_c_int32_t, options, len) &
              == DK_OK, 'adjoint scratch length')
  allocate(tangent_scratch(tlen), scratch(len))
  jv = v
  call expect(dk_sensitivity_spring_sliding_tangent(sys, con, options, 2_c_int32_t, jv, &
                                                    size(jv, kind=c_size_t), tangent_scratch, &
                                                    tlen, index_scratch, &
                                                    size(index_scratch, kind=c_size_t), report) &
              == DK_OK, 'tangent status')
  call expect(logical(report%converged), 'tangent converged')
  g = 0
  call expect(dk_sensitivity_spring_sliding_adjoint(sys, con, options, 2_c_int32_t, w, &
                                                    size(w, kind=c_size_t), g, &
                                                    size(g, kind=c_size_t), scratch, len, &
                                                    index_scratch, &
                                                    size(index_scratch, kind=c_size_t), report) &
              == DK_OK, 'adjoint status')
  call expect(logical(report%converged), 'adjoint converged')
  rel = abs(sum(jv * w) - sum(v * g)) / sqrt(sum(jv * jv) * sum(w * w))
  call expect(rel <= 1e-12_c_double, 'dot-product identity')
  call expect(all(jv(2, 2:NX - 1) == 0), 'tangent on the sliding line')
  call expect(any(jv(1, 2:NX - 1) /= 0), 'the sliding nodes move')
  do k = 1, N
    if (kinds(k) /= 1) call expect(all(g(:, k) == 0), 'adjoint zero off the fixed nodes')
  end do

  ! A stationary method is refused; g keeps its values.
  before = g
  options%method = DK_LINEAR_GAUSS_SEIDEL
  call expect(dk_sensitivity_spring_sliding_adjoint(sys, con, options, 2_c_int32_t, w, &
                                                    size(w, kind=c_size_t), g, &
                                                    size(g, kind=c_size_t), scratch, len, &
                                                    index_scratch, &
                                                    size(index_scratch, kind=c_size_t), report) &
              == DK_ERR_INVALID_PARAMETER, 'Gauss-Seidel refused')
  call expect(all(g == before), 'g untouched')

  if (failures == 0) print '(a)', 'sliding_sensitivity: every check held'

contains

  subroutine edge(a, b)
    integer, intent(in) :: a, b
    e = e + 1
    edges(:, e) = [a, b]
  end subroutine

  subroutine expect(ok, what)
    logical, intent(in) :: ok
    character(*), intent(in) :: what
    if (.not. ok) then
      print '(2a)', 'FAILED: ', what
      failures = failures + 1
    end if
  end subroutine

end program

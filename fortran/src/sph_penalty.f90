!-----------------------------------------------------------------------
!  sph_penalty: interface force between materials (thesis 4-53, 4-54,
!  docs/theory.md s.10).  For a pair whose materials are in
!  different penalty groups, neither of them exempt (a group < 0):
!     pe = (h_i + h_j) / (2 r_ij);  while pe > 1 (repulsive):
!     PB_ij = Pbar (pe^n1 - pe^n2) x_ij / r_ij^2
!     dv_i/dt += PB_ij / m_i,  dv_j/dt -= PB_ij / m_j
!  Integer powers as products.
!-----------------------------------------------------------------------
module sph_penalty
  use iso_c_binding, only: c_int, c_double
  implicit none
  private
  public :: sph_penalty_force

contains

  pure function ipow(x, n) result(y)
    real(c_double), intent(in) :: x
    integer(c_int), intent(in) :: n
    real(c_double) :: y
    integer :: k
    y = 1.0d0
    do k = 1, n
      y = y*x
    end do
  end function ipow

  subroutine sph_penalty_force(dim, ntotal, npair, pair_i, pair_j, x, h, mass, mat, nmat, group, &
      pbar, n1, n2, dvdt) bind(C, name="sph_penalty_force")
    integer(c_int), value :: dim, ntotal, npair, nmat, n1, n2
    real(c_double), value :: pbar
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair), mat(ntotal), group(nmat)
    real(c_double), intent(in) :: x(dim, ntotal), h(ntotal), mass(ntotal)
    real(c_double), intent(out) :: dvdt(dim, ntotal)
    integer :: i, j, k, d
    real(c_double) :: dx(3), r2, pe, f

    dvdt = 0.0d0
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      if (group(mat(i) + 1) == group(mat(j) + 1)) cycle
      if (group(mat(i) + 1) < 0 .or. group(mat(j) + 1) < 0) cycle
      r2 = 0.0d0
      do d = 1, dim
        dx(d) = x(d, i) - x(d, j)
        r2 = r2 + dx(d)*dx(d)
      end do
      pe = 0.5d0*(h(i) + h(j))/sqrt(r2)
      if (pe > 1.0d0) then
        f = pbar*(ipow(pe, n1) - ipow(pe, n2))/r2
        do d = 1, dim
          dvdt(d, i) = dvdt(d, i) + f*dx(d)/mass(i)
          dvdt(d, j) = dvdt(d, j) - f*dx(d)/mass(j)
        end do
      end if
    end do
  end subroutine sph_penalty_force

end module sph_penalty

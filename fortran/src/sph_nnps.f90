!-----------------------------------------------------------------------
!  sph_nnps: nearest-neighbour particle search (Liu & Liu ch. 4:
!  direct_find, link_list).
!
!  Both searches return the same canonical pair list: every pair (i,j)
!  with i < j, i a real particle (index < nreal), j any particle
!  (real or virtual), and |x_i - x_j| < kappa*h_ij, h_ij = (h_i+h_j)/2;
!  sorted by i, then by j.  So the order of every later neighbour sum
!  does not depend on the search used.  Indices are 0-based.
!
!  npair returns the number of pairs found; when it exceeds maxpair
!  only the first maxpair are stored and the caller must grow the
!  arrays and call again.
!
!  The cell search is correct for a per-particle h: the cell edge is
!  kappa*max(h) (Liu's link_list used one global h and could miss
!  pairs when cells were smaller than the support; not reproduced).
!-----------------------------------------------------------------------
module sph_nnps
  use iso_c_binding, only: c_int, c_double
  implicit none
  private
  public :: sph_nnps_direct, sph_nnps_cell

contains

  subroutine sph_nnps_direct(dim, nreal, ntotal, x, h, kappa, maxpair, npair, pair_i, pair_j) &
      bind(C, name="sph_nnps_direct")
    integer(c_int), value :: dim, nreal, ntotal, maxpair
    real(c_double), value :: kappa
    real(c_double), intent(in) :: x(dim, ntotal), h(ntotal)
    integer(c_int), intent(out) :: npair
    integer(c_int), intent(inout) :: pair_i(maxpair), pair_j(maxpair)
    integer :: i, j, d
    real(c_double) :: r2, dxd, s

    npair = 0
    do i = 1, nreal
      do j = i + 1, ntotal
        r2 = 0.0d0
        do d = 1, dim
          dxd = x(d, i) - x(d, j)
          r2 = r2 + dxd*dxd
        end do
        s = kappa*(0.5d0*(h(i) + h(j)))
        if (r2 < s*s) then
          npair = npair + 1
          if (npair <= maxpair) then
            pair_i(npair) = i - 1
            pair_j(npair) = j - 1
          end if
        end if
      end do
    end do
  end subroutine sph_nnps_direct

  subroutine sph_nnps_cell(dim, nreal, ntotal, x, h, kappa, maxpair, npair, pair_i, pair_j) &
      bind(C, name="sph_nnps_cell")
    integer(c_int), value :: dim, nreal, ntotal, maxpair
    real(c_double), value :: kappa
    real(c_double), intent(in) :: x(dim, ntotal), h(ntotal)
    integer(c_int), intent(out) :: npair
    integer(c_int), intent(inout) :: pair_i(maxpair), pair_j(maxpair)
    integer, allocatable :: head(:), next(:), cell(:), cand(:)
    integer :: i, j, d, nc(3), ci(3), lo(3), hi(3), c1, c2, c3, ic, ncand, ncell, k, m, t
    real(c_double) :: xmin(3), xmax(3), cs, hmax, r2, dxd, s
    integer(kind=8) :: prod

    npair = 0
    if (ntotal <= 0) return
    hmax = maxval(h)
    do d = 1, dim
      xmin(d) = minval(x(d, :))
      xmax(d) = maxval(x(d, :))
    end do
    cs = kappa*hmax
    ! keep the grid no larger than a few cells per particle (sparse clouds)
    do
      prod = 1
      do d = 1, dim
        prod = prod*(int((xmax(d) - xmin(d))/cs, kind=8) + 1)
      end do
      if (prod <= max(64_8, 8_8*int(ntotal, kind=8))) exit
      cs = cs*2.0d0
    end do
    nc = 1
    do d = 1, dim
      nc(d) = int((xmax(d) - xmin(d))/cs) + 1
    end do
    ncell = nc(1)*nc(2)*nc(3)

    allocate (head(ncell), next(ntotal), cell(ntotal), cand(ntotal))
    head = 0
    ! Liu's linked list: insert in reverse so each cell lists its particles in ascending order
    do j = ntotal, 1, -1
      ci = 0
      do d = 1, dim
        ci(d) = min(nc(d) - 1, max(0, int((x(d, j) - xmin(d))/cs)))
      end do
      ic = 1 + ci(1) + nc(1)*(ci(2) + nc(2)*ci(3))
      cell(j) = ic
      next(j) = head(ic)
      head(ic) = j
    end do

    do i = 1, nreal
      ic = cell(i) - 1
      ci(3) = ic/(nc(1)*nc(2))
      ci(2) = (ic - ci(3)*nc(1)*nc(2))/nc(1)
      ci(1) = ic - nc(1)*(ci(2) + nc(2)*ci(3))
      lo = 0
      hi = 0
      do d = 1, dim
        lo(d) = max(0, ci(d) - 1)
        hi(d) = min(nc(d) - 1, ci(d) + 1)
      end do
      ncand = 0
      do c3 = lo(3), hi(3)
        do c2 = lo(2), hi(2)
          do c1 = lo(1), hi(1)
            j = head(1 + c1 + nc(1)*(c2 + nc(2)*c3))
            do while (j /= 0)
              if (j > i) then
                r2 = 0.0d0
                do d = 1, dim
                  dxd = x(d, i) - x(d, j)
                  r2 = r2 + dxd*dxd
                end do
                s = kappa*(0.5d0*(h(i) + h(j)))
                if (r2 < s*s) then
                  ncand = ncand + 1
                  cand(ncand) = j
                end if
              end if
              j = next(j)
            end do
          end do
        end do
      end do
      ! insertion sort: the pairs of particle i in ascending j
      do k = 2, ncand
        t = cand(k)
        m = k - 1
        do while (m >= 1)
          if (cand(m) <= t) exit
          cand(m + 1) = cand(m)
          m = m - 1
        end do
        cand(m + 1) = t
      end do
      do k = 1, ncand
        npair = npair + 1
        if (npair <= maxpair) then
          pair_i(npair) = i - 1
          pair_j(npair) = cand(k) - 1
        end if
      end do
    end do
    deallocate (head, next, cell, cand)
  end subroutine sph_nnps_cell

end module sph_nnps

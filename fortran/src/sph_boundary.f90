!-----------------------------------------------------------------------
!  sph_boundary: virtual particles (Liu's virt_part / ext_force,
!  thesis 4-6-1).
!
!  A wall is a segment: seg(1:dim) start a, seg(dim+1:2dim) end b,
!  seg(2dim+1:3dim) the unit normal pointing into the domain.  In 1D a
!  wall is a point (a = b).
!
!  Type I: wall particles at nodes a + k ds t (k = 0..nk, nk =
!  nint(L/spacing), ds = L/nk; the end node only where endnode /= 0, so
!  a corner shared by two walls is counted once).  A real particle
!  closer than r0 to a wall particle gets the central force per unit
!  mass  D [(r0/r)^n1 - (r0/r)^n2] x_ij / r^2  (Liu: n1 = 12, n2 = 4).
!
!  Type II: mirror images of the real particles closer than kappa h to
!  a wall, and images of those images in a second wall (corners).  A
!  mirror copies rho, p, c, e, h, m, mat of its source; position,
!  velocity (free slip: normal component reversed; no slip: all
!  reversed) and deviatoric stress (M tau M, M = I - 2 n n^T) are
!  reflected.  They are rebuilt every step, after the real particles.
!-----------------------------------------------------------------------
module sph_boundary
  use iso_c_binding, only: c_int, c_double
  use sph_param, only: nstr
  implicit none
  private
  public :: sph_boundary_wall_force, sph_boundary_mirror_make, sph_boundary_mirror_fill, &
            sph_boundary_mirror_copy

  integer, parameter :: iv(3, 3) = reshape([1, 4, 5, 4, 2, 6, 5, 6, 3], [3, 3])

contains

  ! tangent t, length L, normal nrm of segment s
  pure subroutine seg_frame(dim, sg, t, el, nrm)
    integer(c_int), intent(in) :: dim
    real(c_double), intent(in) :: sg(3*dim)
    real(c_double), intent(out) :: t(3), el, nrm(3)
    integer :: d
    t = 0.0d0
    nrm = 0.0d0
    el = 0.0d0
    do d = 1, dim
      t(d) = sg(dim + d) - sg(d)
      el = el + t(d)*t(d)
      nrm(d) = sg(2*dim + d)
    end do
    el = sqrt(el)
    if (el > 0.0d0) then
      do d = 1, dim
        t(d) = t(d)/el
      end do
    end if
  end subroutine seg_frame

  subroutine sph_boundary_wall_force(dim, n, x, nseg, seg, endnode, spacing, r0, dcoef, n1, n2, &
      dvdt) bind(C, name="sph_boundary_wall_force")
    integer(c_int), value :: dim, n, nseg, n1, n2
    real(c_double), value :: spacing, r0, dcoef
    real(c_double), intent(in) :: x(dim, n), seg(3*dim, nseg)
    integer(c_int), intent(in) :: endnode(nseg)
    real(c_double), intent(out) :: dvdt(dim, n)
    integer :: i, s, k, d, nk, klo, khi, m
    real(c_double) :: t(3), nrm(3), el, ds, tp, dx(3), r2, q, q1, q2, f

    dvdt = 0.0d0
    do i = 1, n
      do s = 1, nseg
        call seg_frame(dim, seg(:, s), t, el, nrm)
        nk = max(1, nint(el/spacing))
        ds = el/dble(nk)
        tp = 0.0d0
        do d = 1, dim
          tp = tp + (x(d, i) - seg(d, s))*t(d)
        end do
        if (el > 0.0d0) then
          klo = max(0, ceiling((tp - r0)/ds))
          khi = floor((tp + r0)/ds)
          if (endnode(s) /= 0) then
            khi = min(nk, khi)
          else
            khi = min(nk - 1, khi)
          end if
        else
          klo = 0
          khi = 0
        end if
        do k = klo, khi
          r2 = 0.0d0
          do d = 1, dim
            dx(d) = x(d, i) - (seg(d, s) + dble(k)*ds*t(d))
            r2 = r2 + dx(d)*dx(d)
          end do
          if (r2 < r0*r0) then
            q = r0/sqrt(r2)
            q1 = 1.0d0
            do m = 1, n1
              q1 = q1*q
            end do
            q2 = 1.0d0
            do m = 1, n2
              q2 = q2*q
            end do
            f = dcoef*(q1 - q2)/r2
            do d = 1, dim
              dvdt(d, i) = dvdt(d, i) + f*dx(d)
            end do
          end if
        end do
      end do
    end do
  end subroutine sph_boundary_wall_force

  ! is point y within the mirror band of segment sg (0 <= distance < band, along the segment)?
  pure logical function in_band(dim, sg, y, band)
    integer(c_int), intent(in) :: dim
    real(c_double), intent(in) :: sg(3*dim), y(dim), band
    real(c_double) :: t(3), nrm(3), el, dn, tp
    integer :: d
    call seg_frame(dim, sg, t, el, nrm)
    dn = 0.0d0
    tp = 0.0d0
    do d = 1, dim
      dn = dn + (y(d) - sg(d))*nrm(d)
      tp = tp + (y(d) - sg(d))*t(d)
    end do
    in_band = dn >= 0.0d0 .and. dn < band .and. tp >= -band .and. tp <= el + band
  end function in_band

  pure subroutine reflect_point(dim, sg, y)
    integer(c_int), intent(in) :: dim
    real(c_double), intent(in) :: sg(3*dim)
    real(c_double), intent(inout) :: y(dim)
    real(c_double) :: dn
    integer :: d
    dn = 0.0d0
    do d = 1, dim
      dn = dn + (y(d) - sg(d))*sg(2*dim + d)
    end do
    do d = 1, dim
      y(d) = y(d) - 2.0d0*dn*sg(2*dim + d)
    end do
  end subroutine reflect_point

  ! list the mirrors: gsrc(g) the source (0-based), gseg(1:2,g) the walls (0-based, -1 = none)
  subroutine sph_boundary_mirror_make(dim, n, x, h, kappa, nseg, seg, maxg, ng, gsrc, gseg) &
      bind(C, name="sph_boundary_mirror_make")
    integer(c_int), value :: dim, n, nseg, maxg
    real(c_double), value :: kappa
    real(c_double), intent(in) :: x(dim, n), h(n), seg(3*dim, nseg)
    integer(c_int), intent(out) :: ng
    integer(c_int), intent(inout) :: gsrc(maxg), gseg(2, maxg)
    integer :: i, s, t, g, ng1
    real(c_double) :: y(3)

    ng = 0
    do i = 1, n
      do s = 1, nseg
        if (in_band(dim, seg(:, s), x(:, i), kappa*h(i))) then
          ng = ng + 1
          if (ng <= maxg) then
            gsrc(ng) = i - 1
            gseg(1, ng) = s - 1
            gseg(2, ng) = -1
          end if
        end if
      end do
    end do
    if (ng > maxg) return
    ng1 = ng
    do g = 1, ng1
      i = gsrc(g) + 1
      s = gseg(1, g) + 1
      y(1:dim) = x(:, i)
      call reflect_point(dim, seg(:, s), y(1:dim))
      do t = s + 1, nseg
        if (in_band(dim, seg(:, t), y(1:dim), kappa*h(i))) then
          ng = ng + 1
          if (ng <= maxg) then
            gsrc(ng) = i - 1
            gseg(1, ng) = s - 1
            gseg(2, ng) = t - 1
          end if
        end if
      end do
    end do
  end subroutine sph_boundary_mirror_make

  ! fill slots n+1..n+ng of the particle arrays with the mirrors
  subroutine sph_boundary_mirror_fill(dim, ntotal, n, ng, gsrc, gseg, nseg, seg, noslip, x, v, &
      rho, p, c, e, h, mass, mat, ntau, tau) bind(C, name="sph_boundary_mirror_fill")
    integer(c_int), value :: dim, ntotal, n, ng, nseg, noslip, ntau
    integer(c_int), intent(in) :: gsrc(ng), gseg(2, ng)
    real(c_double), intent(in) :: seg(3*dim, nseg)
    real(c_double), intent(inout) :: x(dim, ntotal), v(dim, ntotal), rho(ntotal), p(ntotal), &
                                     c(ntotal), e(ntotal), h(ntotal), mass(ntotal), &
                                     tau(nstr, max(ntau, 1))
    integer(c_int), intent(inout) :: mat(ntotal)
    integer :: g, i, m, l, s, d, a, b, q
    real(c_double) :: vn, nrm(3), rm(3, 3), t3(3, 3), u3(3, 3), sm

    do g = 1, ng
      i = gsrc(g) + 1
      m = n + g
      do d = 1, dim
        x(d, m) = x(d, i)
        v(d, m) = v(d, i)
      end do
      rho(m) = rho(i)
      p(m) = p(i)
      c(m) = c(i)
      e(m) = e(i)
      h(m) = h(i)
      mass(m) = mass(i)
      mat(m) = mat(i)
      if (ntau > 0) then
        do a = 1, 3
          do b = 1, 3
            t3(a, b) = tau(iv(a, b), i)
          end do
        end do
      end if
      do l = 1, 2
        s = gseg(l, g) + 1
        if (s <= 0) cycle
        call reflect_point(dim, seg(:, s), x(:, m))
        nrm = 0.0d0
        do d = 1, dim
          nrm(d) = seg(2*dim + d, s)
        end do
        if (noslip == 0) then
          vn = 0.0d0
          do d = 1, dim
            vn = vn + v(d, m)*nrm(d)
          end do
          do d = 1, dim
            v(d, m) = v(d, m) - 2.0d0*vn*nrm(d)
          end do
        end if
        if (ntau > 0) then
          do a = 1, 3
            do b = 1, 3
              rm(a, b) = -2.0d0*nrm(a)*nrm(b)
              if (a == b) rm(a, b) = rm(a, b) + 1.0d0
            end do
          end do
          do a = 1, 3
            do b = 1, 3
              sm = 0.0d0
              do q = 1, 3
                sm = sm + t3(a, q)*rm(q, b)
              end do
              u3(a, b) = sm
            end do
          end do
          do a = 1, 3
            do b = 1, 3
              sm = 0.0d0
              do q = 1, 3
                sm = sm + rm(a, q)*u3(q, b)
              end do
              t3(a, b) = sm
            end do
          end do
        end if
      end do
      if (noslip /= 0) then
        do d = 1, dim
          v(d, m) = -v(d, i)
        end do
      end if
      if (ntau > 0) then
        do a = 1, 3
          do b = a, 3
            tau(iv(a, b), m) = t3(a, b)
          end do
        end do
      end if
    end do
  end subroutine sph_boundary_mirror_fill

  ! f(n+g) = f(source of g): refresh one field of the mirrors
  subroutine sph_boundary_mirror_copy(ntotal, n, ng, gsrc, f) bind(C, name="sph_boundary_mirror_copy")
    integer(c_int), value :: ntotal, n, ng
    integer(c_int), intent(in) :: gsrc(ng)
    real(c_double), intent(inout) :: f(ntotal)
    integer :: g

    do g = 1, ng
      f(n + g) = f(gsrc(g) + 1)
    end do
  end subroutine sph_boundary_mirror_copy

end module sph_boundary

!-----------------------------------------------------------------------
!  sph_boundary: virtual particles (Liu's virt_part / ext_force,
!  thesis 4-6-1).
!
!  A wall is a segment: seg(1:dim) start a, seg(dim+1:2dim) end b,
!  seg(2dim+1:3dim) the unit normal pointing into the domain.  In 1D a
!  wall is a point (a = b).  In 3D a wall is a parallelogram (a plane
!  wall): seg(1:3) a corner a, seg(4:6) and seg(7:9) its edge vectors u
!  and v, seg(10:12) the unit normal; nsv = 3*dim + 3*(dim/3) values a
!  wall (3, 6, 12), the normal always the last dim of them.
!
!  Type I: wall particles at nodes a + k ds t (k = 0..nk, nk =
!  nint(L/spacing), ds = L/nk; the end node only where endnode /= 0, so
!  a corner shared by two walls is counted once).  A real particle
!  closer than r0 to a wall particle gets the central force per unit
!  mass  D [(r0/r)^n1 - (r0/r)^n2] x_ij / r^2  (Liu: n1 = 12, n2 = 4).
!  In 3D the wall particles are the nodes a + k1 ds1 u/|u| + k2 ds2 v/|v|
!  (k1 = 0..nk1, k2 = 0..nk2), and endnode is a mask of the edges the wall
!  owns (a node on an edge it does not own belongs to another wall):
!  1 the edge k1 = nk1, 2 the edge k2 = nk2, 4 the edge k1 = 0, 8 k2 = 0.
!
!  Type II: mirror images of the real particles closer than kappa h to
!  a wall, and images of those images in a second wall (corners), and in
!  3D in a third (the corner of three planes).  A
!  mirror copies rho, p, c, e, h, m, mat of its source; position,
!  velocity (free slip: normal component reversed; no slip: all
!  reversed) and deviatoric stress (M tau M, M = I - 2 n n^T) are
!  reflected.  They are rebuilt every step, after the real particles.
!
!  Repulsion of boundary particles (Liu & Liu 2003's ext_force): the
!  acceleration of each of the nt particles starts at grav (ngrav = dim
!  values, or 0 for none); then for each pair k in order with one
!  ordinary real particle o (bnd = 0) and one boundary particle b
!  (bnd /= 0; particles n+1..nt are neither), dx = x_o - x_b,
!  rr = |dx|; while rr < r0, with q = r0/rr,
!     dvdt(:, o) += dd*dx*f,  f = (q**p1 - q**p2)/rr**2  (m/s^2).
!-----------------------------------------------------------------------
module sph_boundary
  use iso_c_binding, only: c_int, c_double
  use sph_param, only: nstr
  implicit none
  private
  public :: sph_boundary_wall_force, sph_boundary_mirror_make, sph_boundary_mirror_fill, &
            sph_boundary_mirror_copy, sph_boundary_repulsion

  integer, parameter :: iv(3, 3) = reshape([1, 4, 5, 4, 2, 6, 5, 6, 3], [3, 3])

contains

  ! tangent t, length L, normal nrm of segment s (1D, 2D)
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

  ! unit edge directions t1, t2, edge lengths el1, el2 and normal nrm of a 3D wall
  pure subroutine plane_frame(sg, t1, el1, t2, el2, nrm)
    real(c_double), intent(in) :: sg(12)
    real(c_double), intent(out) :: t1(3), el1, t2(3), el2, nrm(3)
    integer :: d
    el1 = 0.0d0
    el2 = 0.0d0
    do d = 1, 3
      t1(d) = sg(3 + d)
      t2(d) = sg(6 + d)
      el1 = el1 + t1(d)*t1(d)
      el2 = el2 + t2(d)*t2(d)
      nrm(d) = sg(9 + d)
    end do
    el1 = sqrt(el1)
    el2 = sqrt(el2)
    do d = 1, 3
      t1(d) = t1(d)/el1
      t2(d) = t2(d)/el2
    end do
  end subroutine plane_frame

  ! the type I force of the 3D walls on the n real particles (added to dvdt)
  subroutine wall_force_3d(n, x, nseg, seg, endnode, spacing, r0, dcoef, n1, n2, dvdt)
    integer(c_int), intent(in) :: n, nseg, n1, n2
    real(c_double), intent(in) :: spacing, r0, dcoef
    real(c_double), intent(in) :: x(3, n), seg(12, nseg)
    integer(c_int), intent(in) :: endnode(nseg)
    real(c_double), intent(inout) :: dvdt(3, n)
    integer :: i, s, k1, k2, d, nk1, nk2, lo1, hi1, lo2, hi2, m
    real(c_double) :: t1(3), t2(3), nrm(3), el1, el2, ds1, ds2, tp1, tp2, dx(3), r2, q, q1, q2, f

    do i = 1, n
      do s = 1, nseg
        call plane_frame(seg(:, s), t1, el1, t2, el2, nrm)
        nk1 = max(1, nint(el1/spacing))
        nk2 = max(1, nint(el2/spacing))
        ds1 = el1/dble(nk1)
        ds2 = el2/dble(nk2)
        tp1 = 0.0d0
        tp2 = 0.0d0
        do d = 1, 3
          tp1 = tp1 + (x(d, i) - seg(d, s))*t1(d)
          tp2 = tp2 + (x(d, i) - seg(d, s))*t2(d)
        end do
        lo1 = max(0, ceiling((tp1 - r0)/ds1))
        hi1 = min(nk1, floor((tp1 + r0)/ds1))
        lo2 = max(0, ceiling((tp2 - r0)/ds2))
        hi2 = min(nk2, floor((tp2 + r0)/ds2))
        if (iand(endnode(s), 1) == 0) hi1 = min(nk1 - 1, hi1)
        if (iand(endnode(s), 2) == 0) hi2 = min(nk2 - 1, hi2)
        if (iand(endnode(s), 4) == 0) lo1 = max(1, lo1)
        if (iand(endnode(s), 8) == 0) lo2 = max(1, lo2)
        do k2 = lo2, hi2
          do k1 = lo1, hi1
            r2 = 0.0d0
            do d = 1, 3
              dx(d) = x(d, i) - (seg(d, s) + dble(k1)*ds1*t1(d) + dble(k2)*ds2*t2(d))
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
              do d = 1, 3
                dvdt(d, i) = dvdt(d, i) + f*dx(d)
              end do
            end if
          end do
        end do
      end do
    end do
  end subroutine wall_force_3d

  subroutine sph_boundary_wall_force(dim, n, x, nseg, seg, endnode, spacing, r0, dcoef, n1, n2, &
      dvdt) bind(C, name="sph_boundary_wall_force")
    integer(c_int), value :: dim, n, nseg, n1, n2
    real(c_double), value :: spacing, r0, dcoef
    real(c_double), intent(in) :: x(dim, n), seg(3*dim + 3*(dim/3), nseg)
    integer(c_int), intent(in) :: endnode(nseg)
    real(c_double), intent(out) :: dvdt(dim, n)
    integer :: i, s, k, d, nk, klo, khi, m
    real(c_double) :: t(3), nrm(3), el, ds, tp, dx(3), r2, q, q1, q2, f

    dvdt = 0.0d0
    if (dim == 3) then
      call wall_force_3d(n, x, nseg, seg, endnode, spacing, r0, dcoef, n1, n2, dvdt)
      return
    end if
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

  subroutine sph_boundary_repulsion(dim, nt, n, npair, pair_i, pair_j, x, bnd, r0, dd, p1, p2, &
      ngrav, grav, dvdt) bind(C, name="sph_boundary_repulsion")
    integer(c_int), value :: dim, nt, n, npair, ngrav
    real(c_double), value :: r0, dd, p1, p2
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair), bnd(n)
    real(c_double), intent(in) :: x(dim, nt), grav(ngrav)
    real(c_double), intent(out) :: dvdt(dim, nt)
    integer :: i, j, k, d, o, b
    real(c_double) :: dx(3), rr, q, f

    dvdt = 0.0d0
    if (ngrav == dim) then
      do i = 1, nt
        do d = 1, dim
          dvdt(d, i) = grav(d)
        end do
      end do
    end if
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      if (i > n .or. j > n) cycle
      if (bnd(i) == 0 .and. bnd(j) /= 0) then
        o = i
        b = j
      else if (bnd(j) == 0 .and. bnd(i) /= 0) then
        o = j
        b = i
      else
        cycle
      end if
      rr = 0.0d0
      do d = 1, dim
        dx(d) = x(d, o) - x(d, b)
        rr = rr + dx(d)*dx(d)
      end do
      rr = sqrt(rr)
      if (rr < r0) then
        q = r0/rr
        f = (q**p1 - q**p2)/(rr*rr)
        do d = 1, dim
          dvdt(d, o) = dvdt(d, o) + dd*dx(d)*f
        end do
      end if
    end do
  end subroutine sph_boundary_repulsion

  ! is point y within the mirror band of segment sg (0 <= distance < band, along the segment)?
  pure logical function in_band(dim, sg, y, band)
    integer(c_int), intent(in) :: dim
    real(c_double), intent(in) :: sg(3*dim + 3*(dim/3)), y(dim), band
    real(c_double) :: t(3), nrm(3), el, dn, tp, t2(3), el2, tp2
    integer :: d
    if (dim == 3) then
      call plane_frame(sg, t, el, t2, el2, nrm)
      dn = 0.0d0
      tp = 0.0d0
      tp2 = 0.0d0
      do d = 1, 3
        dn = dn + (y(d) - sg(d))*nrm(d)
        tp = tp + (y(d) - sg(d))*t(d)
        tp2 = tp2 + (y(d) - sg(d))*t2(d)
      end do
      in_band = dn >= 0.0d0 .and. dn < band .and. tp >= -band .and. tp <= el + band .and. &
                tp2 >= -band .and. tp2 <= el2 + band
      return
    end if
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
    real(c_double), intent(in) :: sg(3*dim + 3*(dim/3))
    real(c_double), intent(inout) :: y(dim)
    real(c_double) :: dn
    integer :: d, no
    ! the normal is the last dim values of the wall
    no = 2*dim + 3*(dim/3)
    dn = 0.0d0
    do d = 1, dim
      dn = dn + (y(d) - sg(d))*sg(no + d)
    end do
    do d = 1, dim
      y(d) = y(d) - 2.0d0*dn*sg(no + d)
    end do
  end subroutine reflect_point

  ! list the mirrors: gsrc(g) the source (0-based), gseg(1:ngen,g) the walls (0-based, -1 =
  ! none), ngen = 2 + dim/3 generations of images (3 in 3D). A particle i is mirrored when it lies
  ! within kappa*(h(i) + hmax)/2 of a wall, hmax the largest h: the farthest any real particle j
  ! reaches (a pair interacts within kappa*(h(i) + h(j))/2), so that a particle with a large h
  ! near a wall sees the images of every particle it sees on its own side
  subroutine sph_boundary_mirror_make(dim, n, x, h, kappa, nseg, seg, maxg, ng, gsrc, gseg) &
      bind(C, name="sph_boundary_mirror_make")
    integer(c_int), value :: dim, n, nseg, maxg
    real(c_double), value :: kappa
    real(c_double), intent(in) :: x(dim, n), h(n), seg(3*dim + 3*(dim/3), nseg)
    integer(c_int), intent(out) :: ng
    integer(c_int), intent(inout) :: gsrc(maxg), gseg(2 + dim/3, maxg)
    integer :: i, s, t, u, g, ng1, ng2
    real(c_double) :: y(3), hmax

    hmax = 0.0d0
    do i = 1, n
      hmax = max(hmax, h(i))
    end do
    ng = 0
    do i = 1, n
      do s = 1, nseg
        if (in_band(dim, seg(:, s), x(:, i), kappa*(0.5d0*(h(i) + hmax)))) then
          ng = ng + 1
          if (ng <= maxg) then
            gsrc(ng) = i - 1
            gseg(1, ng) = s - 1
            gseg(2, ng) = -1
            if (dim == 3) gseg(3, ng) = -1
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
        if (in_band(dim, seg(:, t), y(1:dim), kappa*(0.5d0*(h(i) + hmax)))) then
          ng = ng + 1
          if (ng <= maxg) then
            gsrc(ng) = i - 1
            gseg(1, ng) = s - 1
            gseg(2, ng) = t - 1
            if (dim == 3) gseg(3, ng) = -1
          end if
        end if
      end do
    end do
    if (dim /= 3 .or. ng > maxg) return
    ! 3D: images of the corner images in a third wall
    ng2 = ng
    do g = ng1 + 1, ng2
      i = gsrc(g) + 1
      s = gseg(1, g) + 1
      t = gseg(2, g) + 1
      y = x(:, i)
      call reflect_point(dim, seg(:, s), y)
      call reflect_point(dim, seg(:, t), y)
      do u = t + 1, nseg
        if (in_band(dim, seg(:, u), y, kappa*(0.5d0*(h(i) + hmax)))) then
          ng = ng + 1
          if (ng <= maxg) then
            gsrc(ng) = i - 1
            gseg(1, ng) = s - 1
            gseg(2, ng) = t - 1
            gseg(3, ng) = u - 1
          end if
        end if
      end do
    end do
  end subroutine sph_boundary_mirror_make

  ! fill slots n+1..n+ng of the particle arrays with the mirrors
  subroutine sph_boundary_mirror_fill(dim, ntotal, n, ng, gsrc, gseg, nseg, seg, noslip, x, v, &
      rho, p, c, e, h, mass, mat, ntau, tau) bind(C, name="sph_boundary_mirror_fill")
    integer(c_int), value :: dim, ntotal, n, ng, nseg, noslip, ntau
    integer(c_int), intent(in) :: gsrc(ng), gseg(2 + dim/3, ng)
    real(c_double), intent(in) :: seg(3*dim + 3*(dim/3), nseg)
    real(c_double), intent(inout) :: x(dim, ntotal), v(dim, ntotal), rho(ntotal), p(ntotal), &
                                     c(ntotal), e(ntotal), h(ntotal), mass(ntotal), &
                                     tau(nstr, max(ntau, 1))
    integer(c_int), intent(inout) :: mat(ntotal)
    integer :: g, i, m, l, s, d, a, b, q, no
    real(c_double) :: vn, nrm(3), rm(3, 3), t3(3, 3), u3(3, 3), sm

    no = 2*dim + 3*(dim/3)

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
      do l = 1, 2 + dim/3
        s = gseg(l, g) + 1
        if (s <= 0) cycle
        call reflect_point(dim, seg(:, s), x(:, m))
        nrm = 0.0d0
        do d = 1, dim
          nrm(d) = seg(no + d, s)
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

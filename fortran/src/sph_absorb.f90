!-----------------------------------------------------------------------
!  sph_absorb: absorbing walls, viscous dampers of the Lysmer-Kuhlemeyer
!  kind (Lysmer & Kuhlemeyer 1969, J. Eng. Mech. Div. ASCE 95(EM4)
!  859-877; docs/theory.md, "Absorbing walls").
!
!  A wall is a segment as in sph_boundary (seg(nsv, nseg), nsv =
!  3*dim + 3*(dim/3), the inward unit normal its last dim values).  The
!  real particles within the layer L in front of it (0 <= d_n < L, d_n
!  the distance along the inward normal n, within the wall's extent;
!  a particle behind the wall counts at d_n = 0) feel, per unit mass,
!
!    a = w(d_n) [ -c_p v_n n - c_s (v - v_n n) + (sigma0 . (-n))/rho ]
!
!  w(d) = 2 (1 - d/L)/L (1/m): its midpoint sum over a lattice of rows
!  d = (k + 1/2) dx is 1/dx, so the rows of one column together take
!  the traction rho c_p v_n (normal) and rho c_s v_t (tangential) of
!  the dashpots, and the traction of the initial stress sigma0 that the
!  domain cut away carried (the static reaction).  c_p^2 = c^2 +
!  4 G / (3 rho), c_s^2 = G / rho, c the EOS's bulk sound speed, G the
!  shear modulus (0 for a fluid).
!
!  sigma0 (nstr, n) is the stress at t = 0: -p I + tau (tension
!  positive), stored by sph_absorb_init.
!-----------------------------------------------------------------------
module sph_absorb
  use iso_c_binding, only: c_int, c_double
  use sph_param, only: nstr, npar, mp_shear
  implicit none
  private
  public :: sph_absorb_init, sph_absorb_dashpot

  integer, parameter :: iv(3, 3) = reshape([1, 4, 5, 4, 2, 6, 5, 6, 3], [3, 3])

contains

  ! sigma0 = -p I + tau of the n real particles (tau absent: ntau = 0)
  subroutine sph_absorb_init(n, p, ntau, tau, sigma0) bind(C, name="sph_absorb_init")
    integer(c_int), value :: n, ntau
    real(c_double), intent(in) :: p(n), tau(nstr, max(ntau, 1))
    real(c_double), intent(out) :: sigma0(nstr, n)
    integer :: i, k
    do i = 1, n
      do k = 1, nstr
        sigma0(k, i) = 0.0d0
        if (ntau > 0) sigma0(k, i) = tau(k, i)
      end do
      do k = 1, 3
        sigma0(k, i) = sigma0(k, i) - p(i)
      end do
    end do
  end subroutine sph_absorb_init

  ! the dashpot and static-reaction acceleration of the n real particles
  subroutine sph_absorb_dashpot(dim, n, x, v, rho, c, mat, nmat, mpar, sigma0, nseg, seg, layer, &
      dvdt) bind(C, name="sph_absorb_dashpot")
    integer(c_int), value :: dim, n, nmat, nseg
    real(c_double), value :: layer
    real(c_double), intent(in) :: x(dim, n), v(dim, n), rho(n), c(n), mpar(npar, nmat), &
                                  sigma0(nstr, n), seg(3*dim + 3*(dim/3), nseg)
    integer(c_int), intent(in) :: mat(n)
    real(c_double), intent(out) :: dvdt(dim, n)
    integer :: i, s, d, b, no
    real(c_double) :: g, cp, cs, nrm(3), t1(3), t2(3), el1, el2, dn, tp1, tp2, w, vn, t0, r
    logical :: inside

    no = 2*dim + 3*(dim/3)
    dvdt = 0.0d0
    do i = 1, n
      g = mpar(mp_shear, mat(i) + 1)
      if (g < 0.0d0) g = 0.0d0
      cp = sqrt(c(i)*c(i) + 4.0d0*g/(3.0d0*rho(i)))
      cs = sqrt(g/rho(i))
      do s = 1, nseg
        call frame(dim, seg(:, s), no, nrm, t1, el1, t2, el2)
        dn = 0.0d0
        tp1 = 0.0d0
        tp2 = 0.0d0
        do d = 1, dim
          r = x(d, i) - seg(d, s)
          dn = dn + r*nrm(d)
          tp1 = tp1 + r*t1(d)
          tp2 = tp2 + r*t2(d)
        end do
        inside = dn < layer
        if (dim >= 2) inside = inside .and. tp1 >= 0.0d0 .and. tp1 <= el1
        if (dim == 3) inside = inside .and. tp2 >= 0.0d0 .and. tp2 <= el2
        if (.not. inside) cycle
        if (dn < 0.0d0) dn = 0.0d0
        w = 2.0d0*(1.0d0 - dn/layer)/layer
        vn = 0.0d0
        do d = 1, dim
          vn = vn + v(d, i)*nrm(d)
        end do
        do d = 1, dim
          ! the traction of the initial stress on the outward normal -n
          t0 = 0.0d0
          do b = 1, dim
            t0 = t0 - sigma0(iv(d, b), i)*nrm(b)
          end do
          dvdt(d, i) = dvdt(d, i) + w*((-cp*vn*nrm(d) - cs*(v(d, i) - vn*nrm(d))) + t0/rho(i))
        end do
      end do
    end do
  end subroutine sph_absorb_dashpot

  ! the inward normal of a wall and its unit edge direction(s) with their lengths (1D: none)
  pure subroutine frame(dim, sg, no, nrm, t1, el1, t2, el2)
    integer(c_int), intent(in) :: dim
    integer, intent(in) :: no
    real(c_double), intent(in) :: sg(3*dim + 3*(dim/3))
    real(c_double), intent(out) :: nrm(3), t1(3), el1, t2(3), el2
    integer :: d
    nrm = 0.0d0
    t1 = 0.0d0
    t2 = 0.0d0
    el1 = 0.0d0
    el2 = 0.0d0
    do d = 1, dim
      nrm(d) = sg(no + d)
    end do
    if (dim == 2) then
      do d = 1, 2
        t1(d) = sg(2 + d) - sg(d)
        el1 = el1 + t1(d)*t1(d)
      end do
    else if (dim == 3) then
      do d = 1, 3
        t1(d) = sg(3 + d)
        t2(d) = sg(6 + d)
        el1 = el1 + t1(d)*t1(d)
        el2 = el2 + t2(d)*t2(d)
      end do
    end if
    el1 = sqrt(el1)
    el2 = sqrt(el2)
    if (el1 > 0.0d0) then
      do d = 1, 3
        t1(d) = t1(d)/el1
      end do
    end if
    if (el2 > 0.0d0) then
      do d = 1, 3
        t2(d) = t2(d)/el2
      end do
    end if
  end subroutine frame

end module sph_absorb

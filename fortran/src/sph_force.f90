!-----------------------------------------------------------------------
!  sph_force: internal force (Liu's int_force, thesis 4-33..4-38 with
!  the sign as docs/theory.md s.5 states it), sigma = -p delta + tau:
!     dv_i^a/dt = sum_j m_j (sig_i^ab/rho_i^2 + sig_j^ab/rho_j^2) dW_ij/dx_i^b
!     de_i/dt   = 1/2 sum_j m_j (p_i/rho_i^2 + p_j/rho_j^2) (v_i - v_j).grad_i W_ij
!  or, with eform = 1 (the asymmetric form, each particle its own p dV work):
!     de_i/dt   = sum_j m_j (p_i/rho_i^2) (v_i - v_j).grad_i W_ij
!  which conserves the same total energy with the momentum equation above
!  and keeps e >= 0 where p >= 0 (docs/theory.md s.5).
!  The deviatoric work tau:epsdot/rho is added by the strength module.
!  Axisymmetric (nrinv = ntotal, rinv = 1/r* of sph_geometry, mass the
!  planar masses mu): the energy terms read v_i - (r_j/r_i) v_j at the i
!  end and (r_i/r_j) v_i - v_j at the j end in place of v_i - v_j, so
!  that the pair's work on the rings' internal energies, m_i de_i +
!  m_j de_j with m = 2 pi r mu, is exactly what its forces take from
!  their kinetic energies (the total energy is conserved; the hoop part
!  -(p/rho) v_r/r of the p dV work is in the sum; docs/theory.md s.16).
!  In a pair across the axis (the other end a mirror, 1/r* < 0) the real
!  end's term is (p_i/rho_i^2 + p_j/rho_j^2) v_i.grad_i W_ij: its internal
!  energy takes the work of the mirror's force on it (the axis does no
!  work on the rings' total energy).
!  With pform = 1 (the interface form of Colagrossi & Landrini 2003, for
!  phases of very different density) every sig_i/rho_i^2 + sig_j/rho_j^2
!  reads (sig_i + sig_j)/(rho_i rho_j), and the asymmetric energy term
!  p_i/rho_i^2 reads p_i/(rho_i rho_j): the pair's force and work stay
!  equal and opposite, so the total energy is conserved as before.
!  ntau = 0: fluids, pressure only; ntau = ntotal: tau(6, ntotal) in the
!  order xx, yy, zz, xy, xz, yz.
!-----------------------------------------------------------------------
module sph_force
  use iso_c_binding, only: c_int, c_double
  use sph_param
  implicit none
  private
  public :: sph_force_internal, sph_force_newtonian

  integer, parameter :: iv(3, 3) = reshape([1, 4, 5, 4, 2, 6, 5, 6, 3], [3, 3])

contains

  subroutine sph_force_internal(dim, ntotal, npair, pair_i, pair_j, dwdx, mass, rho, p, v, &
      ntau, tau, eform, pform, nrinv, rinv, dvdt, dedt) bind(C, name="sph_force_internal")
    integer(c_int), value :: dim, ntotal, npair, ntau, eform, pform, nrinv
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: dwdx(dim, npair), mass(ntotal), rho(ntotal), p(ntotal), &
                                  v(dim, ntotal), tau(nstr, max(ntau, 1)), rinv(max(nrinv, 1))
    real(c_double), intent(out) :: dvdt(dim, ntotal), dedt(ntotal)
    integer :: i, j, k, a, b
    real(c_double) :: pr, vd, f, de, ri2, rj2, s, vdi, vdj, sij, sji, vwi, vwj, ci, cj, di, dj, &
                      rr, qi, qj

    dvdt = 0.0d0
    dedt = 0.0d0
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      ri2 = rho(i)*rho(i)
      rj2 = rho(j)*rho(j)
      rr = rho(i)*rho(j)
      if (pform == 0) then
        pr = p(i)/ri2 + p(j)/rj2
        qi = p(i)/ri2
        qj = p(j)/rj2
      else
        pr = (p(i) + p(j))/rr
        qi = p(i)/rr
        qj = p(j)/rr
      end if
      vd = 0.0d0
      if (nrinv == 0) then
        do a = 1, dim
          vd = vd + (v(a, i) - v(a, j))*dwdx(a, k)
        end do
      end if
      if (ntau == 0) then
        do a = 1, dim
          f = pr*dwdx(a, k)
          dvdt(a, i) = dvdt(a, i) - mass(j)*f
          dvdt(a, j) = dvdt(a, j) + mass(i)*f
        end do
      else
        do a = 1, dim
          f = 0.0d0
          do b = 1, dim
            if (pform /= 0 .and. a == b) then
              s = ((tau(iv(a, b), i) - p(i)) + (tau(iv(a, b), j) - p(j)))/rr
            else if (pform /= 0) then
              s = (tau(iv(a, b), i) + tau(iv(a, b), j))/rr
            else if (a == b) then
              s = (tau(iv(a, b), i) - p(i))/ri2 + (tau(iv(a, b), j) - p(j))/rj2
            else
              s = tau(iv(a, b), i)/ri2 + tau(iv(a, b), j)/rj2
            end if
            f = f + s*dwdx(b, k)
          end do
          dvdt(a, i) = dvdt(a, i) + mass(j)*f
          dvdt(a, j) = dvdt(a, j) - mass(i)*f
        end do
      end if
      if (nrinv > 0) then
        sji = rinv(i)/rinv(j)
        sij = rinv(j)/rinv(i)
        vdi = 0.0d0
        vdj = 0.0d0
        vwi = 0.0d0
        vwj = 0.0d0
        do a = 1, dim
          vdi = vdi + (v(a, i) - sji*v(a, j))*dwdx(a, k)
          vdj = vdj + (sij*v(a, i) - v(a, j))*dwdx(a, k)
          vwi = vwi + v(a, i)*dwdx(a, k)
          vwj = vwj + v(a, j)*dwdx(a, k)
        end do
        if (eform == 0) then
          ci = 0.5d0*pr
          cj = 0.5d0*pr
        else
          ci = qi
          cj = qj
        end if
        ! a pair across the axis (the other end an image, 1/r* < 0): the real ring's internal
        ! energy takes the work of the image's force on it
        if (rinv(j) < 0.0d0) then
          di = pr*vwi
        else
          di = ci*vdi
        end if
        if (rinv(i) < 0.0d0) then
          dj = -(pr*vwj)
        else
          dj = cj*vdj
        end if
        dedt(i) = dedt(i) + mass(j)*di
        dedt(j) = dedt(j) + mass(i)*dj
      else if (eform == 0) then
        de = 0.5d0*pr*vd
        dedt(i) = dedt(i) + mass(j)*de
        dedt(j) = dedt(j) + mass(i)*de
      else
        dedt(i) = dedt(i) + mass(j)*(qi*vd)
        dedt(j) = dedt(j) + mass(i)*(qj*vd)
      end if
    end do
  end subroutine sph_force_internal

  !---------------------------------------------------------------------
  !  sph_force_newtonian: the physical (Newtonian) viscosity of Liu &
  !  Liu's book (int_force with visc on, pa_sph = 2), in its order.
  !  Per particle the shear strain rate (1/s), dv = v_j - v_i:
  !     eps_i^ab = sum_j m_j/rho_j (dv^a dW/dx_i^b + dv^b dW/dx_i^a
  !                - 2/3 delta^ab dv.grad_i W)
  !  (per pair 2/3 (2 dv_a w_a - sum_{c /= a} dv_c w_c) for ab = aa,
  !  dv_a w_b + dv_b w_a else; t += (m_j h)/rho_j at i, (m_i h)/rho_i
  !  at j); the viscous heating (J/kg/s)
  !     de_i/dt = ((1/2 eta_i)/rho_i) eps_i:eps_i
  !  (eps:eps = xx^2 + 2xy^2 + 2xz^2 + yy^2 + 2yz^2 + zz^2, the book's
  !  order); the acceleration (m/s^2)
  !     dv_i^a/dt = sum_j m_j (eta_i eps_i^ab/rho_i^2
  !                 + eta_j eps_j^ab/rho_j^2) dW/dx_i^b
  !  (b ascending from 0, + m_j f at i, - m_i f at j).  eta: the dynamic
  !  viscosity (Pa s) of every particle.
  !---------------------------------------------------------------------
  subroutine sph_force_newtonian(dim, ntotal, npair, pair_i, pair_j, dwdx, mass, rho, v, eta, &
      dvdt, dedt) bind(C, name="sph_force_newtonian")
    integer(c_int), value :: dim, ntotal, npair
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: dwdx(dim, npair), mass(ntotal), rho(ntotal), v(dim, ntotal), &
                                  eta(ntotal)
    real(c_double), intent(out) :: dvdt(dim, ntotal), dedt(ntotal)
    real(c_double), allocatable :: t(:, :)
    real(c_double) :: dv(3), hs(nstr), f, s, ri2, rj2
    integer :: i, j, k, a, b, q

    allocate(t(nstr, ntotal))
    t = 0.0d0
    dvdt = 0.0d0
    dedt = 0.0d0
    hs = 0.0d0
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      do a = 1, dim
        dv(a) = v(a, j) - v(a, i)
      end do
      if (dim == 1) then
        hs(1) = 2.0d0*dv(1)*dwdx(1, k)
      else if (dim == 2) then
        hs(1) = 2.0d0*dv(1)*dwdx(1, k) - dv(2)*dwdx(2, k)
        hs(4) = dv(1)*dwdx(2, k) + dv(2)*dwdx(1, k)
        hs(2) = 2.0d0*dv(2)*dwdx(2, k) - dv(1)*dwdx(1, k)
      else
        hs(1) = 2.0d0*dv(1)*dwdx(1, k) - dv(2)*dwdx(2, k) - dv(3)*dwdx(3, k)
        hs(4) = dv(1)*dwdx(2, k) + dv(2)*dwdx(1, k)
        hs(5) = dv(1)*dwdx(3, k) + dv(3)*dwdx(1, k)
        hs(2) = 2.0d0*dv(2)*dwdx(2, k) - dv(1)*dwdx(1, k) - dv(3)*dwdx(3, k)
        hs(6) = dv(2)*dwdx(3, k) + dv(3)*dwdx(2, k)
        hs(3) = 2.0d0*dv(3)*dwdx(3, k) - dv(1)*dwdx(1, k) - dv(2)*dwdx(2, k)
      end if
      do a = 1, dim
        hs(a) = (2.0d0/3.0d0)*hs(a)
      end do
      do q = 1, nstr
        t(q, i) = t(q, i) + mass(j)*hs(q)/rho(j)
        t(q, j) = t(q, j) + mass(i)*hs(q)/rho(i)
      end do
    end do
    do i = 1, ntotal
      if (dim == 1) then
        s = t(1, i)*t(1, i)
      else if (dim == 2) then
        s = t(1, i)*t(1, i) + 2.0d0*t(4, i)*t(4, i) + t(2, i)*t(2, i)
      else
        s = t(1, i)*t(1, i) + 2.0d0*t(4, i)*t(4, i) + 2.0d0*t(5, i)*t(5, i) + t(2, i)*t(2, i) &
            + 2.0d0*t(6, i)*t(6, i) + t(3, i)*t(3, i)
      end if
      dedt(i) = 0.5d0*eta(i)/rho(i)*s
    end do
    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      ri2 = rho(i)*rho(i)
      rj2 = rho(j)*rho(j)
      do a = 1, dim
        f = 0.0d0
        do b = 1, dim
          q = iv(a, b)
          f = f + (eta(i)*t(q, i)/ri2 + eta(j)*t(q, j)/rj2)*dwdx(b, k)
        end do
        dvdt(a, i) = dvdt(a, i) + mass(j)*f
        dvdt(a, j) = dvdt(a, j) - mass(i)*f
      end do
    end do
    deallocate(t)
  end subroutine sph_force_newtonian

end module sph_force

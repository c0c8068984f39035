!-----------------------------------------------------------------------
!  sph_integrator: leapfrog as in Liu's time_integration (thesis
!  2-17..2-27), generalised to a variable step.  The staggered
!  variables u = rho (continuity), e, v, tau live at half steps.
!   predict (steps after the first), with the rates of the last step:
!       u_min = u ;  u(t_n) = u_min + dt_prev/2 * du
!   advance, first step:  u(t_1/2) = u(t_0) + dt/2 * du(t_0)
!            later steps: u(t_n+1/2) = u_min + (dt_prev + dt)/2 * du(t_n)
!            then x(t_n+1) = x(t_n) + dt * (v(t_n+1/2) + av)
!  For a fixed step (dt_prev = dt) this is Liu's scheme exactly.
!  Boundary particles (bnd(i) = 1 integrated, 2 held; nbnd = n, or 0 for
!  none): x is never moved; a held particle's rho, e, v, tau keep their
!  values (u_min is still saved), the virtual particles of Liu & Liu (2003).
!  sum_rates adds the acceleration terms in a fixed order, then gravity.
!  efloor: e_i = max(e_i, 0), returning the energy added, sum_i m_i max(0, -e_i)
!  (J; booked in the energy balance by the solver).
!  clamp: rho_i = min(max(rho_i, lo), hi) after each density update, as the
!  dam-break time_integration of G.R. Liu and M.B. Liu (2003) does (kg/m^3).
!  cfl: dt = C min_i min( h_i/(c_i + |v_i| + kv mumax_i), sqrt(h_i/|a_i|) ),
!  kv mumax_i the signal speed of the viscosity's beta term (nmu = n), or
!  no such term (nmu = 0); then, where a material has a physical viscosity
!  eta (neta > 0), dt = min(dt, min_i 0.125 rho_i h_i^2/eta_i), the diffusion
!  limit of Morris, Fox and Zhu (1997), in particle order.
!-----------------------------------------------------------------------
module sph_integrator
  use iso_c_binding, only: c_int, c_double
  use sph_param, only: nstr
  implicit none
  private
  public :: sph_integrator_sum_rates, sph_integrator_predict, sph_integrator_advance, &
            sph_integrator_cfl, sph_integrator_efloor, sph_integrator_clamp

contains

  ! dv(d,i) = acc_1(d,i) + ... + acc_nterm(d,i) + grav(d); term t of the
  ! stacked array holds (d,i) at acc(d + dim*(i-1), t); a boundary particle
  ! (nbnd = n, bnd(i) /= 0) takes no gravity
  subroutine sph_integrator_sum_rates(dim, n, lda, nterm, acc, grav, dv, nbnd, bnd) &
      bind(C, name="sph_integrator_sum_rates")
    integer(c_int), value :: dim, n, lda, nterm, nbnd
    integer(c_int), intent(in) :: bnd(max(nbnd, 1))
    real(c_double), intent(in) :: acc(lda, max(nterm, 1)), grav(dim)
    real(c_double), intent(out) :: dv(dim, n)
    integer :: i, d, t, l
    real(c_double) :: s
    logical :: fixed

    do i = 1, n
      fixed = .false.
      if (nbnd > 0) fixed = bnd(i) /= 0
      do d = 1, dim
        l = d + dim*(i - 1)
        s = 0.0d0
        if (nterm > 0) s = acc(l, 1)
        do t = 2, nterm
          s = s + acc(l, t)
        end do
        if (fixed) then
          dv(d, i) = s
        else
          dv(d, i) = s + grav(d)
        end if
      end do
    end do
  end subroutine sph_integrator_sum_rates

  ! true where particle i is a held boundary particle
  pure logical function held(nbnd, bnd, i)
    integer(c_int), intent(in) :: nbnd, bnd(max(nbnd, 1))
    integer, intent(in) :: i

    held = .false.
    if (nbnd > 0) held = bnd(i) == 2
  end function held

  subroutine sph_integrator_predict(dim, n, ntau, dt_prev, cont, rho, drho, e, de, v, dv, tau, &
      dtau, rho_min, e_min, v_min, tau_min, nbnd, bnd) bind(C, name="sph_integrator_predict")
    integer(c_int), value :: dim, n, ntau, cont, nbnd
    integer(c_int), intent(in) :: bnd(max(nbnd, 1))
    real(c_double), value :: dt_prev
    real(c_double), intent(inout) :: rho(n), e(n), v(dim, n), tau(nstr, max(ntau, 1))
    real(c_double), intent(in) :: drho(n), de(n), dv(dim, n), dtau(nstr, max(ntau, 1))
    real(c_double), intent(out) :: rho_min(n), e_min(n), v_min(dim, n), tau_min(nstr, max(ntau, 1))
    integer :: i, d
    real(c_double) :: half
    logical :: hold

    half = 0.5d0*dt_prev
    do i = 1, n
      hold = held(nbnd, bnd, i)
      e_min(i) = e(i)
      if (.not. hold) e(i) = e(i) + half*de(i)
      if (cont /= 0) then
        rho_min(i) = rho(i)
        if (.not. hold) rho(i) = rho(i) + half*drho(i)
      end if
      do d = 1, dim
        v_min(d, i) = v(d, i)
        if (.not. hold) v(d, i) = v(d, i) + half*dv(d, i)
      end do
    end do
    do i = 1, ntau
      hold = held(nbnd, bnd, i)
      do d = 1, nstr
        tau_min(d, i) = tau(d, i)
        if (.not. hold) tau(d, i) = tau(d, i) + half*dtau(d, i)
      end do
    end do
  end subroutine sph_integrator_predict

  subroutine sph_integrator_advance(dim, n, ntau, first, dt_prev, dt, cont, rho, drho, e, de, &
      v, dv, tau, dtau, rho_min, e_min, v_min, tau_min, nav, av, x, nbnd, bnd) &
      bind(C, name="sph_integrator_advance")
    integer(c_int), value :: dim, n, ntau, first, cont, nav, nbnd
    integer(c_int), intent(in) :: bnd(max(nbnd, 1))
    real(c_double), value :: dt_prev, dt
    real(c_double), intent(inout) :: rho(n), e(n), v(dim, n), tau(nstr, max(ntau, 1)), x(dim, n)
    real(c_double), intent(in) :: drho(n), de(n), dv(dim, n), dtau(nstr, max(ntau, 1)), &
                                  rho_min(n), e_min(n), v_min(dim, n), tau_min(nstr, max(ntau, 1)), &
                                  av(dim, max(nav, 1))
    integer :: i, d
    real(c_double) :: s

    if (first /= 0) then
      s = 0.5d0*dt
      do i = 1, n
        if (held(nbnd, bnd, i)) cycle
        e(i) = e(i) + s*de(i)
        if (cont /= 0) rho(i) = rho(i) + s*drho(i)
        do d = 1, dim
          v(d, i) = v(d, i) + s*dv(d, i)
        end do
      end do
      do i = 1, ntau
        if (held(nbnd, bnd, i)) cycle
        do d = 1, nstr
          tau(d, i) = tau(d, i) + s*dtau(d, i)
        end do
      end do
    else
      s = 0.5d0*(dt_prev + dt)
      do i = 1, n
        if (held(nbnd, bnd, i)) cycle
        e(i) = e_min(i) + s*de(i)
        if (cont /= 0) rho(i) = rho_min(i) + s*drho(i)
        do d = 1, dim
          v(d, i) = v_min(d, i) + s*dv(d, i)
        end do
      end do
      do i = 1, ntau
        if (held(nbnd, bnd, i)) cycle
        do d = 1, nstr
          tau(d, i) = tau_min(d, i) + s*dtau(d, i)
        end do
      end do
    end if
    do i = 1, n
      if (nbnd > 0) then
        if (bnd(i) /= 0) cycle
      end if
      do d = 1, dim
        if (nav > 0) then
          x(d, i) = x(d, i) + dt*(v(d, i) + av(d, i))
        else
          x(d, i) = x(d, i) + dt*v(d, i)
        end if
      end do
    end do
  end subroutine sph_integrator_advance

  subroutine sph_integrator_cfl(dim, n, cfl, h, c, v, dv, nmu, kv, mumax, neta, eta, mat, rho, &
      dt) bind(C, name="sph_integrator_cfl")
    integer(c_int), value :: dim, n, nmu, neta
    real(c_double), value :: cfl, kv
    real(c_double), intent(in) :: h(n), c(n), v(dim, n), dv(dim, n), mumax(max(nmu, 1))
    real(c_double), intent(in) :: eta(max(neta, 1))
    integer(c_int), intent(in) :: mat(*)
    real(c_double), intent(in) :: rho(*)
    real(c_double), intent(out) :: dt
    integer :: i, d
    real(c_double) :: vv, aa, tc, tf, tv

    dt = huge(1.0d0)
    do i = 1, n
      vv = 0.0d0
      aa = 0.0d0
      do d = 1, dim
        vv = vv + v(d, i)*v(d, i)
        aa = aa + dv(d, i)*dv(d, i)
      end do
      if (nmu > 0) then
        tc = h(i)/(c(i) + sqrt(vv) + kv*mumax(i))
      else
        tc = h(i)/(c(i) + sqrt(vv))
      end if
      dt = min(dt, tc)
      if (aa > 0.0d0) then
        tf = sqrt(h(i)/sqrt(aa))
        dt = min(dt, tf)
      end if
    end do
    dt = cfl*dt
    if (neta > 0) then
      do i = 1, n
        if (eta(mat(i) + 1) > 0.0d0) then
          tv = 0.125d0*rho(i)*h(i)*h(i)/eta(mat(i) + 1)
          dt = min(dt, tv)
        end if
      end do
    end if
  end subroutine sph_integrator_cfl

  subroutine sph_integrator_efloor(n, mass, e, added) bind(C, name="sph_integrator_efloor")
    integer(c_int), value :: n
    real(c_double), intent(in) :: mass(n)
    real(c_double), intent(inout) :: e(n)
    real(c_double), intent(out) :: added
    integer :: i

    added = 0.0d0
    do i = 1, n
      if (e(i) < 0.0d0) then
        added = added - mass(i)*e(i)
        e(i) = 0.0d0
      end if
    end do
  end subroutine sph_integrator_efloor

  ! rho below lo becomes lo, above hi becomes hi; a NaN is left as it is
  subroutine sph_integrator_clamp(n, lo, hi, rho) bind(C, name="sph_integrator_clamp")
    integer(c_int), value :: n
    real(c_double), value :: lo, hi
    real(c_double), intent(inout) :: rho(n)
    integer :: i

    do i = 1, n
      if (rho(i) < lo) then
        rho(i) = lo
      else if (rho(i) > hi) then
        rho(i) = hi
      end if
    end do
  end subroutine sph_integrator_clamp

end module sph_integrator

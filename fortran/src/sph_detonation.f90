!-----------------------------------------------------------------------
!  sph_detonation: lighting of the charge (docs/theory.md s.9).
!  Instantaneous (constant-volume) burn needs no routine: the JWL
!  products start at rho0, e0.  Programmed burn: the front leaves the
!  lighting point xdet at the detonation speed D; particle i lights at
!  t_i = |x_i - xdet| / D (or, lit along a plane through xdet with unit
!  normal nrm (plane = 1), t_i = |(x_i - xdet).nrm| / D) and its burn
!  fraction is
!     lam_i = 1 if t >= t_i else 0                      (width = 0)
!     lam_i = min(1, max(0, (t - t_i) D / (width h_i)))  (width > 0)
!  The lighting speed is sf D (sf = 1: the thesis's reading; below 1 the
!  lighting lags the front, so that the beta burn carries it).
!  Beta burn (Wilkins; mpar(mp_eta_cj) = rho_CJ/rho0 > 1): an explosive
!  compressed towards its CJ density burns too, and never un-burns,
!     lam_i <- max(lam_i, lam_prog, min(1, (1 - rho0/rho_i)/(1 - 1/eta_CJ)))
!  (burn is then read as the previous step's fraction, 0 at the start).
!  The JWL pressure is multiplied by lam_i (sph_eos: the unreacted
!  explosive carries the rest, when it has an EOS).
!-----------------------------------------------------------------------
module sph_detonation
  use iso_c_binding, only: c_int, c_double
  use sph_param
  implicit none
  private
  public :: sph_detonation_light, sph_detonation_burn

contains

  subroutine sph_detonation_light(dim, n, x, mat, nmat, mtype, mpar, xdet, nrm, plane, sf, &
      tlight) bind(C, name="sph_detonation_light")
    integer(c_int), value :: dim, n, nmat, plane
    real(c_double), value :: sf
    integer(c_int), intent(in) :: mat(n), mtype(nmat)
    real(c_double), intent(in) :: x(dim, n), mpar(npar, nmat), xdet(dim), nrm(dim)
    real(c_double), intent(out) :: tlight(n)
    integer :: i, m, d
    real(c_double) :: r2, s

    do i = 1, n
      m = mat(i) + 1
      tlight(i) = 0.0d0
      if (mtype(m) == eos_jwl) then
        if (plane /= 0) then
          s = 0.0d0
          do d = 1, dim
            s = s + (x(d, i) - xdet(d))*nrm(d)
          end do
          tlight(i) = abs(s)/(sf*mpar(mp_e1 + 5, m))
        else
          r2 = 0.0d0
          do d = 1, dim
            r2 = r2 + (x(d, i) - xdet(d))*(x(d, i) - xdet(d))
          end do
          tlight(i) = sqrt(r2)/(sf*mpar(mp_e1 + 5, m))
        end if
      end if
    end do
  end subroutine sph_detonation_light

  subroutine sph_detonation_burn(n, t, mat, nmat, mpar, tlight, h, rho, width, burn) &
      bind(C, name="sph_detonation_burn")
    integer(c_int), value :: n, nmat
    real(c_double), value :: t, width
    integer(c_int), intent(in) :: mat(n)
    real(c_double), intent(in) :: mpar(npar, nmat), tlight(n), h(n), rho(n)
    real(c_double), intent(inout) :: burn(n)
    integer :: i, m
    real(c_double) :: lam, fb

    do i = 1, n
      m = mat(i) + 1
      if (width <= 0.0d0) then
        if (t >= tlight(i)) then
          lam = 1.0d0
        else
          lam = 0.0d0
        end if
      else
        lam = min(1.0d0, max(0.0d0, (t - tlight(i))*mpar(mp_e1 + 5, m)/(width*h(i))))
      end if
      if (mpar(mp_eta_cj, m) > 1.0d0) then
        fb = (1.0d0 - mpar(mp_rho0, m)/rho(i))/(1.0d0 - 1.0d0/mpar(mp_eta_cj, m))
        burn(i) = max(burn(i), lam, min(1.0d0, fb))
      else
        burn(i) = lam
      end if
    end do
  end subroutine sph_detonation_burn

end module sph_detonation

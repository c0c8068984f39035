!-----------------------------------------------------------------------
!  sph_param: named constants shared by the legacy SPH modules.
!
!  Only parameters live here (no SAVE, no COMMON, no mutable state).
!  The material table mpar(SPH_NPAR, nmat) is laid out by the row
!  indices below; the same numbers are #defined in
!  include/blastsph_legacy.h so that the Rust side fills the table in
!  the same order.  Indices of particles and pairs at the C boundary
!  are 0-based; the Fortran adds 1 when it indexes its arrays.
!-----------------------------------------------------------------------
module sph_param
  use iso_c_binding, only: c_int, c_double
  implicit none
  public

  real(c_double), parameter :: pi = 3.14159265358979323846d0

  ! kernel codes (skf, as in Liu's code)
  integer(c_int), parameter :: skf_cubic = 1, skf_gauss = 2, skf_quintic = 3, skf_wendland = 4

  ! equation-of-state codes (mtype)
  integer(c_int), parameter :: eos_none = 0, eos_ideal_gas = 1, eos_jwl = 2, &
                               eos_water = 3, eos_soil = 4

  ! rows of the material table mpar(npar, nmat)
  integer(c_int), parameter :: mp_rho0 = 1          ! reference density (kg/m^3)
  integer(c_int), parameter :: mp_e1 = 2            ! first EOS constant (see below)
  ! ideal gas : e1 = gamma
  ! JWL       : e1..e6 = A (Pa), B (Pa), R1, R2, omega, D (m/s)
  ! water     : e1..e6 = a1, a2, a3 (Pa), b0, b1, C0 (m/s)
  ! soil (MG) : e1..e3 = C (m/s), S, Gamma
  integer(c_int), parameter :: mp_pmin = 8          ! pressure floor (Pa), -huge = none
  integer(c_int), parameter :: mp_shear = 9         ! shear modulus G (Pa), 0 = no strength
  integer(c_int), parameter :: mp_alpha_phi = 10    ! Drucker-Prager alpha_phi
  integer(c_int), parameter :: mp_cohesion = 11     ! Drucker-Prager k (Pa)
  ! JWL explosives: the unreacted explosive (Mie-Grueneisen with a linear
  ! Us-Up Hugoniot; 0 = a void, the thesis's reading), the chemical energy
  ! that its e counts (at rest), and the CJ compression of the beta burn
  integer(c_int), parameter :: mp_unr_c = 12        ! C of Us = C + S Up (m/s)
  integer(c_int), parameter :: mp_unr_s = 13        ! S
  integer(c_int), parameter :: mp_unr_gamma = 14    ! Grueneisen Gamma
  integer(c_int), parameter :: mp_echem = 15        ! e of the unreacted at rest (J/kg)
  integer(c_int), parameter :: mp_eta_cj = 16       ! rho_CJ/rho0 of the beta burn (0 = off)
  integer(c_int), parameter :: npar = 16

  ! number of stored deviatoric stress components: xx, yy, zz, xy, xz, yz
  integer(c_int), parameter :: nstr = 6
end module sph_param

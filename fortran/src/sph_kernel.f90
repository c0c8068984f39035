!-----------------------------------------------------------------------
!  sph_kernel: smoothing kernel W(r,h) and its gradient (thesis 5-1,
!  Liu & Liu ch. 3).  Codes: 1 cubic spline, 2 Gauss, 3 quintic spline
!  (Morris 1996), 4 Wendland C2.  q = r/h.
!
!  dwdx is grad_i W_ij = dW/dr * (x_i - x_j)/r, written as
!  alpha * g(q) * (x_i - x_j) / h**2 so that r = 0 is harmless.
!  Integer powers are written as products (bit parity with Rust).
!-----------------------------------------------------------------------
module sph_kernel
  use iso_c_binding, only: c_int, c_double
  use sph_param
  implicit none
  private
  public :: kernel_w_dw, kernel_support, sph_kernel_pairs, sph_kernel_self, sph_kernel_point

contains

  pure function kernel_support(skf) result(kappa)
    integer(c_int), intent(in) :: skf
    real(c_double) :: kappa
    select case (skf)
    case (skf_gauss, skf_quintic)
      kappa = 3.0d0
    case default
      kappa = 2.0d0
    end select
  end function kernel_support

  pure function kernel_alpha(dim, skf, h) result(alpha)
    integer(c_int), intent(in) :: dim, skf
    real(c_double), intent(in) :: h
    real(c_double) :: alpha
    alpha = 0.0d0
    select case (skf)
    case (skf_cubic)
      if (dim == 1) then
        alpha = 1.0d0/h
      else if (dim == 2) then
        alpha = 15.0d0/(7.0d0*pi*h*h)
      else
        alpha = 3.0d0/(2.0d0*pi*h*h*h)
      end if
    case (skf_gauss)
      if (dim == 1) then
        alpha = 1.0d0/(sqrt(pi)*h)
      else if (dim == 2) then
        alpha = 1.0d0/(pi*h*h)
      else
        alpha = 1.0d0/(pi*sqrt(pi)*h*h*h)
      end if
    case (skf_quintic)
      if (dim == 1) then
        alpha = 1.0d0/(120.0d0*h)
      else if (dim == 2) then
        alpha = 7.0d0/(478.0d0*pi*h*h)
      else
        alpha = 1.0d0/(120.0d0*pi*h*h*h)
      end if
    case (skf_wendland)
      if (dim == 1) then
        alpha = 5.0d0/(8.0d0*h)
      else if (dim == 2) then
        alpha = 7.0d0/(4.0d0*pi*h*h)
      else
        alpha = 21.0d0/(16.0d0*pi*h*h*h)
      end if
    end select
  end function kernel_alpha

  ! W and grad W for one separation dx (length dim), distance r, length h
  pure subroutine kernel_w_dw(dim, skf, r, dx, h, w, dwdx)
    integer(c_int), intent(in) :: dim, skf
    real(c_double), intent(in) :: r, dx(dim), h
    real(c_double), intent(out) :: w, dwdx(dim)
    real(c_double) :: q, alpha, g, a, b, c, a2, b2, c2
    integer :: d

    q = r/h
    alpha = kernel_alpha(dim, skf, h)
    w = 0.0d0
    g = 0.0d0
    select case (skf)
    case (skf_cubic)
      if (q < 1.0d0) then
        w = alpha*(2.0d0/3.0d0 - q*q + 0.5d0*q*q*q)
        g = alpha*(-2.0d0 + 1.5d0*q)
      else if (q < 2.0d0) then
        a = 2.0d0 - q
        w = alpha*(a*a*a/6.0d0)
        g = -alpha*0.5d0*a*a/q
      end if
    case (skf_gauss)
      if (q < 3.0d0) then
        a = exp(-q*q)
        w = alpha*a
        g = -2.0d0*alpha*a
      end if
    case (skf_quintic)
      if (q < 3.0d0) then
        a = 3.0d0 - q
        a2 = a*a
        w = a2*a2*a
        g = -5.0d0*a2*a2
        if (q < 2.0d0) then
          b = 2.0d0 - q
          b2 = b*b
          w = w - 6.0d0*b2*b2*b
          g = g + 30.0d0*b2*b2
          if (q < 1.0d0) then
            c = 1.0d0 - q
            c2 = c*c
            w = w + 15.0d0*c2*c2*c
            g = -120.0d0 + 120.0d0*q*q - 50.0d0*q*q*q
          else
            g = g/q
          end if
        else
          g = g/q
        end if
        w = alpha*w
        g = alpha*g
      end if
    case (skf_wendland)
      if (q < 2.0d0) then
        a = 1.0d0 - 0.5d0*q
        if (dim == 1) then
          w = alpha*a*a*a*(1.5d0*q + 1.0d0)
          g = -3.0d0*alpha*a*a
        else
          w = alpha*a*a*a*a*(2.0d0*q + 1.0d0)
          g = -5.0d0*alpha*a*a*a
        end if
      end if
    end select
    do d = 1, dim
      dwdx(d) = g*dx(d)/(h*h)
    end do
  end subroutine kernel_w_dw

  ! W_ij and grad_i W_ij for every pair, with h_ij = (h_i + h_j)/2; grad W
  ! times gscale when gscale /= 1 (the lattice normalisation 1/S of the
  ! kernel's first moment, sph.lattice_gradient; 1 leaves it as it is)
  subroutine sph_kernel_pairs(dim, ntotal, npair, skf, gscale, pair_i, pair_j, x, h, w, dwdx) &
      bind(C, name="sph_kernel_pairs")
    integer(c_int), value :: dim, ntotal, npair, skf
    real(c_double), value :: gscale
    integer(c_int), intent(in) :: pair_i(npair), pair_j(npair)
    real(c_double), intent(in) :: x(dim, ntotal), h(ntotal)
    real(c_double), intent(out) :: w(npair), dwdx(dim, npair)
    integer :: k, i, j, d
    real(c_double) :: dx(3), r2, hij

    do k = 1, npair
      i = pair_i(k) + 1
      j = pair_j(k) + 1
      r2 = 0.0d0
      do d = 1, dim
        dx(d) = x(d, i) - x(d, j)
        r2 = r2 + dx(d)*dx(d)
      end do
      hij = 0.5d0*(h(i) + h(j))
      call kernel_w_dw(dim, skf, sqrt(r2), dx(1:dim), hij, w(k), dwdx(:, k))
      if (gscale /= 1.0d0) then
        do d = 1, dim
          dwdx(d, k) = dwdx(d, k)*gscale
        end do
      end if
    end do
  end subroutine sph_kernel_pairs

  ! the self-contribution W(0, h_i) of each particle (summation density)
  subroutine sph_kernel_self(dim, n, skf, h, w0) bind(C, name="sph_kernel_self")
    integer(c_int), value :: dim, n, skf
    real(c_double), intent(in) :: h(n)
    real(c_double), intent(out) :: w0(n)
    integer :: i
    real(c_double) :: dx(3), g(3)

    dx = 0.0d0
    do i = 1, n
      call kernel_w_dw(dim, skf, 0.0d0, dx(1:dim), h(i), w0(i), g(1:dim))
    end do
  end subroutine sph_kernel_self

  ! one evaluation, for tests: W and grad W at separation dx
  subroutine sph_kernel_point(dim, skf, dx, h, w, dwdx) bind(C, name="sph_kernel_point")
    integer(c_int), value :: dim, skf
    real(c_double), value :: h
    real(c_double), intent(in) :: dx(dim)
    real(c_double), intent(out) :: w, dwdx(dim)
    real(c_double) :: r2
    integer :: d

    r2 = 0.0d0
    do d = 1, dim
      r2 = r2 + dx(d)*dx(d)
    end do
    call kernel_w_dw(dim, skf, sqrt(r2), dx, h, w, dwdx)
  end subroutine sph_kernel_point

end module sph_kernel

      subroutine kernel(r, dx, hsml, w, dwdx)
c-----------------------------------------------------------------------
c     Smoothing function W(r,h) of one pair and its gradient with
c     respect to the position of the first particle of the pair.
c       skf = 1 : cubic B-spline, support 2h
c       skf = 3 : quintic spline, support 3h
c     r     -- distance of the two particles                      (in)
c     dx    -- x_i - x_j, one value per dimension                 (in)
c     hsml  -- smoothing length used for this pair                (in)
c     w     -- kernel value                                      (out)
c     dwdx  -- kernel gradient, one value per dimension          (out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      double precision r, dx(dim), hsml, w, dwdx(dim)
      double precision q, fac
      integer d

      q = r/hsml
      w = 0.e0
      do 10 d = 1, dim
        dwdx(d) = 0.e0
   10 continue

      if (skf .eq. 1) then
c       normalisation of the cubic spline in 1, 2 and 3 dimensions
        if (dim .eq. 1) then
          fac = 1.e0/hsml
        else if (dim .eq. 2) then
          fac = 15.e0/(7.e0*pi*hsml*hsml)
        else
          fac = 3.e0/(2.e0*pi*hsml*hsml*hsml)
        endif
        if (q .ge. 0. .and. q .le. 1.e0) then
          w = fac*(2./3. - q*q + q**3/2.)
          do 20 d = 1, dim
            dwdx(d) = fac*(-2. + 3./2.*q)/hsml**2*dx(d)
   20     continue
        else if (q .gt. 1.e0 .and. q .le. 2.) then
          w = fac/6.e0*(2. - q)**3
          do 30 d = 1, dim
            dwdx(d) = -fac/6.e0*3.*(2. - q)**2/hsml*(dx(d)/r)
   30     continue
        endif

      else if (skf .eq. 3) then
c       quintic spline (the gradient below q = 1 is the old code's)
        if (dim .eq. 1) then
          fac = 1.e0/(120.e0*hsml)
        else if (dim .eq. 2) then
          fac = 7.e0/(478.e0*pi*hsml*hsml)
        else
          fac = 1.e0/(120.e0*pi*hsml*hsml*hsml)
        endif
        if (q .ge. 0. .and. q .le. 1.) then
          w = fac*((3 - q)**5 - 6*(2 - q)**5 + 15*(1 - q)**5)
          do 40 d = 1, dim
            dwdx(d) = fac*((-120 + 120*q - 50*q**2)/hsml**2*dx(d))
   40     continue
        else if (q .gt. 1. .and. q .le. 2.) then
          w = fac*((3 - q)**5 - 6*(2 - q)**5)
          do 50 d = 1, dim
            dwdx(d) = fac*(-5*(3 - q)**4 + 30*(2 - q)**4)/hsml
     &                *(dx(d)/r)
   50     continue
        else if (q .gt. 2. .and. q .le. 3.) then
          w = fac*(3 - q)**5
          do 60 d = 1, dim
            dwdx(d) = fac*(-5*(3 - q)**4)/hsml*(dx(d)/r)
   60     continue
        endif
      endif

      end

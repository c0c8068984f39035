c----------------------------------------------------------------------
c     Subroutine to return the deviatoric stress of the soil particles
c     to the Drucker-Prager yield surface sqrt(J2) <= 3 alphi p + coh;
c     no strength where 3 alphi p + coh <= 0 (tension cut-off).
c
c     ntotal  : number of particles                              [in]
c     itype   : particle type (2 = soil, < 0 virtual)            [in]
c     p       : pressure                                         [in]
c     sxx, syy, szz, sxy : deviatoric stress                 [in/out]
c----------------------------------------------------------------------
      subroutine dp_yield(ntotal, itype, p, sxx, syy, szz, sxy)
      implicit none
      include 'param.inc'
      include 'soil.inc'
      integer ntotal, itype(maxn), i
      double precision p(maxn), sxx(maxn), syy(maxn), szz(maxn),
     &  sxy(maxn), aj2, yv, sj, f

      do 10 i = 1, ntotal
        if (itype(i) .ne. 2) goto 10
        aj2 = 0.5d0*(sxx(i)*sxx(i) + syy(i)*syy(i) + szz(i)*szz(i))
     &      + sxy(i)*sxy(i)
        yv = 3.d0*alphi*p(i) + coh
        if (yv .le. 0.d0) then
          sxx(i) = 0.d0
          syy(i) = 0.d0
          szz(i) = 0.d0
          sxy(i) = 0.d0
        else
          sj = sqrt(aj2)
          if (sj .gt. yv) then
            f = yv/sj
            sxx(i) = sxx(i)*f
            syy(i) = syy(i)*f
            szz(i) = szz(i)*f
            sxy(i) = sxy(i)*f
          endif
        endif
10    continue
      return
      end

c----------------------------------------------------------------------
c     Subroutine to calculate the strain rate, the rotation rate and
c     the Jaumann rate of the deviatoric stress of the soil particles
c     (plane strain: the out-of-plane rates are zero, szz is kept).
c
c     ntotal  : number of particles (real and virtual)           [in]
c     niac    : number of interaction pairs                      [in]
c     pair_i, pair_j : the pairs                                 [in]
c     dwdx    : kernel gradient of each pair                     [in]
c     mass, rho, vx : particle mass, density, velocity           [in]
c     itype   : particle type (2 = soil, < 0 virtual)            [in]
c     sxx, syy, szz, sxy : deviatoric stress                     [in]
c     epsxx, epsyy, epsxy : strain rate                         [out]
c     rxy     : rotation rate (L_xy - L_yx)/2                   [out]
c     dsxx, dsyy, dszz, dsxy : Jaumann stress rate              [out]
c     dedt    : deviatoric work rate s:eps/rho                  [out]
c----------------------------------------------------------------------
      subroutine strain_rate(ntotal, niac, pair_i, pair_j, dwdx, mass,
     &   rho, vx, itype, sxx, syy, szz, sxy, epsxx, epsyy, epsxy, rxy,
     &   dsxx, dsyy, dszz, dsxy, dedt)
      implicit none
      include 'param.inc'
      include 'soil.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &  pair_j(max_interaction), itype(maxn)
      double precision dwdx(dim, max_interaction), mass(maxn),
     &  rho(maxn), vx(dim, maxn), sxx(maxn), syy(maxn), szz(maxn),
     &  sxy(maxn), epsxx(maxn), epsyy(maxn), epsxy(maxn), rxy(maxn),
     &  dsxx(maxn), dsyy(maxn), dszz(maxn), dsxy(maxn), dedt(maxn)
      integer i, j, k
      double precision dvx, dvy, vi, vj, g2, tr, ezz
      double precision dudx(maxn), dudy(maxn), dvdx(maxn), dvdy(maxn)

      do i = 1, ntotal
        dudx(i) = 0.d0
        dudy(i) = 0.d0
        dvdx(i) = 0.d0
        dvdy(i) = 0.d0
      enddo

c     velocity gradient, both ends of every pair
      do k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        vi = mass(i)/rho(i)
        vj = mass(j)/rho(j)
        dvx = vx(1,j) - vx(1,i)
        dudx(i) = dudx(i) + vj*dvx*dwdx(1,k)
        dudy(i) = dudy(i) + vj*dvx*dwdx(2,k)
        dudx(j) = dudx(j) + vi*dvx*dwdx(1,k)
        dudy(j) = dudy(j) + vi*dvx*dwdx(2,k)
        dvy = vx(2,j) - vx(2,i)
        dvdx(i) = dvdx(i) + vj*dvy*dwdx(1,k)
        dvdy(i) = dvdy(i) + vj*dvy*dwdx(2,k)
        dvdx(j) = dvdx(j) + vi*dvy*dwdx(1,k)
        dvdy(j) = dvdy(j) + vi*dvy*dwdx(2,k)
      enddo

      g2 = 2.d0*gmod
      ezz = 0.d0
      do i = 1, ntotal
        epsxx(i) = 0.5d0*(dudx(i) + dudx(i))
        epsyy(i) = 0.5d0*(dvdy(i) + dvdy(i))
        epsxy(i) = 0.5d0*(dudy(i) + dvdx(i))
        rxy(i) = 0.5d0*(dudy(i) - dvdx(i))
        dsxx(i) = 0.d0
        dsyy(i) = 0.d0
        dszz(i) = 0.d0
        dsxy(i) = 0.d0
        dedt(i) = 0.d0
        if (itype(i) .eq. 2) then
          tr = epsxx(i) + epsyy(i) + ezz
          dsxx(i) = g2*epsxx(i) - g2*tr/3.d0 + sxy(i)*rxy(i)
     &            + rxy(i)*sxy(i)
          dsyy(i) = g2*epsyy(i) - g2*tr/3.d0 - sxy(i)*rxy(i)
     &            - rxy(i)*sxy(i)
          dszz(i) = g2*ezz - g2*tr/3.d0
          dsxy(i) = g2*epsxy(i) - sxx(i)*rxy(i) + rxy(i)*syy(i)
          dedt(i) = (sxx(i)*epsxx(i) + sxy(i)*epsxy(i)
     &            + sxy(i)*epsxy(i) + syy(i)*epsyy(i))/rho(i)
        endif
      enddo
      return
      end

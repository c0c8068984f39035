      subroutine int_force(itimestep, dt, ntotal, hsml, mass, vx, niac,
     &                     rho, eta, pair_i, pair_j, dwdx, u, itype, x,
     &                     t, c, p, dvxdt, tdsdt, dedt)
c-----------------------------------------------------------------------
c     Internal forces: pressure gradient and (with visc) the gradient
c     of the viscous stress, the viscous entropy production and the
c     rate of the specific internal energy.  The pressure and sound
c     speed of every particle are computed here from its equation of
c     state (itype 1: ideal gas, 2: artificial water).
c     itimestep -- time step number (not used)                     (in)
c     dt     -- time step (not used)                               (in)
c     ntotal -- number of particles                                (in)
c     hsml   -- smoothing lengths (not used)                       (in)
c     mass   -- masses                                             (in)
c     vx     -- velocities                                         (in)
c     niac   -- number of pairs                                    (in)
c     rho    -- densities                                          (in)
c     eta    -- dynamic viscosities                                (in)
c     pair_i, pair_j -- the pairs                                  (in)
c     dwdx   -- kernel gradient of each pair                       (in)
c     u      -- specific internal energies                         (in)
c     itype  -- particle types                                     (in)
c     x      -- positions (not used)                               (in)
c     t      -- temperatures (not used)                        (in/out)
c     c      -- sound speeds                                      (out)
c     p      -- pressures                                         (out)
c     dvxdt  -- acceleration                                      (out)
c     tdsdt  -- viscous entropy production                        (out)
c     dedt   -- rate of the specific internal energy              (out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer itimestep, ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction), itype(maxn)
      double precision dt, hsml(maxn), mass(maxn), vx(dim,maxn),
     &        rho(maxn), eta(maxn), dwdx(dim,max_interaction), u(maxn),
     &        x(dim,maxn), t(maxn), c(maxn), p(maxn), dvxdt(dim,maxn),
     &        tdsdt(maxn), dedt(maxn)
      integer i, j, k, d
      double precision dv(dim), sxx(maxn), syy(maxn), szz(maxn),
     &        sxy(maxn), sxz(maxn), syz(maxn), divv(maxn), axx, ayy,
     &        azz, axy, axz, ayz, f, fe, rr, div, gi, gj

      do 10 i = 1, ntotal
        sxx(i) = 0.e0
        syy(i) = 0.e0
        szz(i) = 0.e0
        sxy(i) = 0.e0
        sxz(i) = 0.e0
        syz(i) = 0.e0
        divv(i) = 0.e0
        tdsdt(i) = 0.e0
        dedt(i) = 0.e0
        do 5 d = 1, dim
          dvxdt(d,i) = 0.e0
    5   continue
   10 continue

c     shear strain rate  T_ab = v_a,b + v_b,a - 2/3 delta_ab v_c,c
      if (visc) then
        do 30 k = 1, niac
          i = pair_i(k)
          j = pair_j(k)
          do 15 d = 1, dim
            dv(d) = vx(d,j) - vx(d,i)
   15     continue
          if (dim .eq. 1) then
            axx = 2.e0*dv(1)*dwdx(1,k)
          else if (dim .eq. 2) then
            axx = 2.e0*dv(1)*dwdx(1,k) - dv(2)*dwdx(2,k)
            axy = dv(1)*dwdx(2,k) + dv(2)*dwdx(1,k)
            ayy = 2.e0*dv(2)*dwdx(2,k) - dv(1)*dwdx(1,k)
          else
            axx = 2.e0*dv(1)*dwdx(1,k) - dv(2)*dwdx(2,k)
     &            - dv(3)*dwdx(3,k)
            axy = dv(1)*dwdx(2,k) + dv(2)*dwdx(1,k)
            axz = dv(1)*dwdx(3,k) + dv(3)*dwdx(1,k)
            ayy = 2.e0*dv(2)*dwdx(2,k) - dv(1)*dwdx(1,k)
     &            - dv(3)*dwdx(3,k)
            ayz = dv(2)*dwdx(3,k) + dv(3)*dwdx(2,k)
            azz = 2.e0*dv(3)*dwdx(3,k) - dv(1)*dwdx(1,k)
     &            - dv(2)*dwdx(2,k)
          endif
          axx = 2.e0/3.e0*axx
          if (dim .ge. 2) ayy = 2.e0/3.e0*ayy
          if (dim .eq. 3) azz = 2.e0/3.e0*azz
          sxx(i) = sxx(i) + mass(j)*axx/rho(j)
          sxx(j) = sxx(j) + mass(i)*axx/rho(i)
          if (dim .ge. 2) then
            sxy(i) = sxy(i) + mass(j)*axy/rho(j)
            sxy(j) = sxy(j) + mass(i)*axy/rho(i)
            syy(i) = syy(i) + mass(j)*ayy/rho(j)
            syy(j) = syy(j) + mass(i)*ayy/rho(i)
          endif
          if (dim .eq. 3) then
            sxz(i) = sxz(i) + mass(j)*axz/rho(j)
            sxz(j) = sxz(j) + mass(i)*axz/rho(i)
            syz(i) = syz(i) + mass(j)*ayz/rho(j)
            syz(j) = syz(j) + mass(i)*ayz/rho(i)
            szz(i) = szz(i) + mass(j)*azz/rho(j)
            szz(j) = szz(j) + mass(i)*azz/rho(i)
          endif
c         velocity divergence (kept for the record, not used below)
          div = 0.
          do 20 d = 1, dim
            div = div + dv(d)*dwdx(d,k)
   20     continue
          divv(i) = divv(i) + mass(j)*div/rho(j)
          divv(j) = divv(j) + mass(i)*div/rho(i)
   30   continue
      endif

      do 40 i = 1, ntotal
c       viscous entropy production  T ds/dt = eta/(2 rho) T_ab T_ab
        if (visc) then
          if (dim .eq. 1) then
            tdsdt(i) = sxx(i)*sxx(i)
          else if (dim .eq. 2) then
            tdsdt(i) = sxx(i)*sxx(i) + 2.e0*sxy(i)*sxy(i)
     &                 + syy(i)*syy(i)
          else
            tdsdt(i) = sxx(i)*sxx(i) + 2.e0*sxy(i)*sxy(i)
     &                 + 2.e0*sxz(i)*sxz(i) + syy(i)*syy(i)
     &                 + 2.e0*syz(i)*syz(i) + szz(i)*szz(i)
          endif
          tdsdt(i) = 0.5e0*eta(i)/rho(i)*tdsdt(i)
        endif
c       equation of state
        if (abs(itype(i)) .eq. 1) then
          call p_gas(rho(i), u(i), p(i), c(i))
        else if (abs(itype(i)) .eq. 2) then
          call p_art_water(rho(i), p(i), c(i))
        endif
   40 continue

c     pressure (and viscous) force, and the work of the pressure
      do 70 k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        fe = 0.e0
        rr = 1.e0/(rho(i)*rho(j))
        if (pa_sph .eq. 1) then
          gi = 1.e0
          gj = 1.e0
        else
          gi = rho(i)**2
          gj = rho(j)**2
        endif
        do 60 d = 1, dim
          f = -(p(i)/gi + p(j)/gj)*dwdx(d,k)
          if (pa_sph .eq. 1) f = -(p(i) + p(j))*dwdx(d,k)
          fe = fe + (vx(d,j) - vx(d,i))*f
          if (visc .and. d .eq. 1) then
            f = f + (eta(i)*sxx(i)/gi + eta(j)*sxx(j)/gj)*dwdx(1,k)
            if (dim .ge. 2) f = f + (eta(i)*sxy(i)/gi
     &                     + eta(j)*sxy(j)/gj)*dwdx(2,k)
            if (dim .eq. 3) f = f + (eta(i)*sxz(i)/gi
     &                     + eta(j)*sxz(j)/gj)*dwdx(3,k)
          else if (visc .and. d .eq. 2) then
            f = f + (eta(i)*sxy(i)/gi + eta(j)*sxy(j)/gj)*dwdx(1,k)
     &            + (eta(i)*syy(i)/gi + eta(j)*syy(j)/gj)*dwdx(2,k)
            if (dim .eq. 3) f = f + (eta(i)*syz(i)/gi
     &                     + eta(j)*syz(j)/gj)*dwdx(3,k)
          else if (visc) then
            f = f + (eta(i)*sxz(i)/gi + eta(j)*sxz(j)/gj)*dwdx(1,k)
     &            + (eta(i)*syz(i)/gi + eta(j)*syz(j)/gj)*dwdx(2,k)
     &            + (eta(i)*szz(i)/gi + eta(j)*szz(j)/gj)*dwdx(3,k)
          endif
          if (pa_sph .eq. 1) f = f*rr
          dvxdt(d,i) = dvxdt(d,i) + mass(j)*f
          dvxdt(d,j) = dvxdt(d,j) - mass(i)*f
   60   continue
        if (pa_sph .eq. 1) fe = fe*rr
        dedt(i) = dedt(i) + mass(j)*fe
        dedt(j) = dedt(j) + mass(i)*fe
   70 continue

      do 80 i = 1, ntotal
        dedt(i) = tdsdt(i) + 0.5e0*dedt(i)
   80 continue

      end

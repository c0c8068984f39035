      subroutine h_upgrade(dt, ntotal, mass, vx, rho, niac, pair_i,
     &                     pair_j, dwdx, hsml)
c-----------------------------------------------------------------------
c     Evolution of the smoothing length.
c       sle = 0 : unchanged
c       sle = 1 : h = 2 (m/rho)**(1/dim)
c       sle = 2 : dh/dt = (h/dim) sum_j (m_j/rho_j) (v_j - v_i).grad_i W_ij
c     dt     -- time step                                          (in)
c     ntotal -- number of particles                                (in)
c     mass   -- masses                                             (in)
c     vx     -- velocities                                         (in)
c     rho    -- densities                                          (in)
c     niac   -- number of pairs                                    (in)
c     pair_i, pair_j -- the pairs                                  (in)
c     dwdx   -- kernel gradient of each pair                       (in)
c     hsml   -- smoothing lengths                              (in/out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction)
      double precision dt, mass(maxn), vx(dim,maxn), rho(maxn),
     &        dwdx(dim,max_interaction), hsml(maxn)
      integer i, j, k, d
      double precision fac, dv(dim), div, divv(maxn), dh

      if (sle .eq. 1) then
        fac = 2.0
        do 10 i = 1, ntotal
          hsml(i) = fac*(mass(i)/rho(i))**(1./dim)
   10   continue
      else if (sle .eq. 2) then
        do 20 i = 1, ntotal
          divv(i) = 0.e0
   20   continue
        do 40 k = 1, niac
          i = pair_i(k)
          j = pair_j(k)
          do 30 d = 1, dim
            dv(d) = vx(d,j) - vx(d,i)
   30     continue
          div = dv(1)*dwdx(1,k)
          do 35 d = 2, dim
            div = div + dv(d)*dwdx(d,k)
   35     continue
          divv(i) = divv(i) + mass(j)*div/rho(j)
          divv(j) = divv(j) + mass(i)*div/rho(i)
   40   continue
        do 50 i = 1, ntotal
          dh = (hsml(i)/dim)*divv(i)
          hsml(i) = hsml(i) + dt*dh
          if (hsml(i) .le. 0) hsml(i) = hsml(i) - dt*dh
   50   continue
      endif

      end

      subroutine sum_density(ntotal, hsml, mass, niac, pair_i, pair_j,
     &                       w, itype, rho)
c-----------------------------------------------------------------------
c     Density by summation over the pairs, rho_i = sum_j m_j W_ij,
c     the particle itself included (W at r = 0 from the kernel).
c     With nor_density the sum is divided by the sum of the kernel's
c     volume weights (a Shepard-like normalisation).
c     ntotal -- number of particles                                (in)
c     hsml   -- smoothing lengths                                  (in)
c     mass   -- masses                                             (in)
c     niac   -- number of pairs                                    (in)
c     pair_i, pair_j -- the pairs                                  (in)
c     w      -- kernel of each pair                                (in)
c     itype  -- particle types (not used here)                     (in)
c     rho    -- old density (weights) on entry, new density   (in/out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction), itype(maxn)
      double precision hsml(maxn), mass(maxn), w(max_interaction),
     &        rho(maxn)
      integer i, j, k, d
      double precision w0, zero(dim), r, wsum(maxn)

      r = 0.
      do 10 d = 1, dim
        zero(d) = 0.e0
   10 continue

c     sum of the volume weights m_j/rho_j W_ij (self term first)
      do 20 i = 1, ntotal
        call kernel(r, zero, hsml(i), w0, zero)
        wsum(i) = w0*mass(i)/rho(i)
   20 continue
      do 30 k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        wsum(i) = wsum(i) + mass(j)/rho(j)*w(k)
        wsum(j) = wsum(j) + mass(i)/rho(i)*w(k)
   30 continue

c     the density itself (self term first, then the pairs in order)
      do 40 i = 1, ntotal
        call kernel(r, zero, hsml(i), w0, zero)
        rho(i) = w0*mass(i)
   40 continue
      do 50 k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        rho(i) = rho(i) + mass(j)*w(k)
        rho(j) = rho(j) + mass(i)*w(k)
   50 continue

      if (nor_density) then
        do 60 i = 1, ntotal
          rho(i) = rho(i)/wsum(i)
   60   continue
      endif

      end

      subroutine con_density(ntotal, mass, niac, pair_i, pair_j, dwdx,
     &                       vx, itype, x, rho, drhodt)
c-----------------------------------------------------------------------
c     Rate of change of the density by the continuity equation,
c     drho_i/dt = sum_j m_j (v_i - v_j) . grad_i W_ij
c     ntotal -- number of particles                                (in)
c     mass   -- masses                                             (in)
c     niac   -- number of pairs                                    (in)
c     pair_i, pair_j -- the pairs                                  (in)
c     dwdx   -- kernel gradient of each pair                       (in)
c     vx     -- velocities                                         (in)
c     itype  -- particle types (not used)                          (in)
c     x      -- positions (not used)                               (in)
c     rho    -- densities (not used)                               (in)
c     drhodt -- density rate                                      (out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction), itype(maxn)
      double precision mass(maxn), dwdx(dim,max_interaction),
     &        vx(dim,maxn), x(dim,maxn), rho(maxn), drhodt(maxn)
      integer i, j, k, d
      double precision dv(dim), div

      do 10 i = 1, ntotal
        drhodt(i) = 0.
   10 continue

      do 30 k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        do 20 d = 1, dim
          dv(d) = vx(d,i) - vx(d,j)
   20   continue
        div = dv(1)*dwdx(1,k)
        do 25 d = 2, dim
          div = div + dv(d)*dwdx(d,k)
   25   continue
        drhodt(i) = drhodt(i) + mass(j)*div
        drhodt(j) = drhodt(j) + mass(i)*div
   30 continue

      end

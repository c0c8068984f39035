      subroutine av_vel(ntotal, mass, niac, pair_i, pair_j, w, vx, rho,
     &                  av)
c-----------------------------------------------------------------------
c     Monaghan's averaged velocity (XSPH):
c       av_i = eps sum_j 2 m_j (v_j - v_i)/(rho_i + rho_j) W_ij
c     The caller adds av to the velocity as it is.
c     ntotal -- number of particles                                (in)
c     mass   -- masses                                             (in)
c     niac   -- number of pairs                                    (in)
c     pair_i, pair_j -- the pairs                                  (in)
c     w      -- kernel of each pair                                (in)
c     vx     -- velocities                                         (in)
c     rho    -- densities                                          (in)
c     av     -- velocity correction                               (out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction)
      double precision mass(maxn), w(max_interaction), vx(dim,maxn),
     &        rho(maxn), av(dim,maxn)
      integer i, j, k, d
      double precision eps, dv

c     eps: chosen by experience (about 0.3 at most for the shock tube)
      eps = 0.3

      do 10 i = 1, ntotal
        do 5 d = 1, dim
          av(d,i) = 0.
    5   continue
   10 continue

      do 30 k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        do 20 d = 1, dim
          dv = vx(d,i) - vx(d,j)
          av(d,i) = av(d,i) - 2*mass(j)*dv/(rho(i) + rho(j))*w(k)
          av(d,j) = av(d,j) + 2*mass(i)*dv/(rho(i) + rho(j))*w(k)
   20   continue
   30 continue

      do 40 i = 1, ntotal
        do 35 d = 1, dim
          av(d,i) = eps*av(d,i)
   35   continue
   40 continue

      end

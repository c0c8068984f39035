      subroutine art_heat(ntotal, hsml, mass, x, vx, niac, rho, u, c,
     &                    pair_i, pair_j, w, dwdx, dedt)
c-----------------------------------------------------------------------
c     Artificial heat (Noh 1987, Monaghan 1992): each pair exchanges
c     heat in proportion to the coefficient of its particles
c       q_i = g1 h_i c_i + g2 h_i**2 (|div_i| - div_i),
c       div_i = sum_j m_j/rho_j (v_j - v_i).dW_ij/dx_i,
c     as
c       de_i/dt = 2 sum_j m_j q_ij/(rho_ij (r_ij**2 + 0.01 h_ij**2))
c                          (u_i - u_j) x_ij.dW_ij/dx_i
c     (q_ij, rho_ij, h_ij: means of the pair).
c     ntotal -- number of particles                                (in)
c     hsml   -- smoothing lengths                                  (in)
c     mass   -- masses                                             (in)
c     x      -- positions                                          (in)
c     vx     -- velocities                                         (in)
c     niac   -- number of pairs                                    (in)
c     rho    -- densities                                          (in)
c     u      -- specific internal energies                         (in)
c     c      -- sound speeds                                       (in)
c     pair_i, pair_j -- the pairs                                  (in)
c     w      -- kernel of each pair (not used)                     (in)
c     dwdx   -- kernel gradient of each pair                       (in)
c     dedt   -- heating rate                                      (out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction)
      double precision hsml(maxn), mass(maxn), x(dim,maxn),
     &        vx(dim,maxn), rho(maxn), u(maxn), c(maxn),
     &        w(max_interaction), dwdx(dim,max_interaction), dedt(maxn)
      integer i, j, k, d
      double precision g1, g2
c     g1: the linear (sound speed) term, g2: the quadratic term, which
c     acts only where the flow is compressed
      parameter (g1 = 0.1, g2 = 1.0)
      double precision divv(maxn), dvdw, hij, rhoij, r2, sep, xdw,
     &        qi, qj, qij, fac

      do 10 i = 1, ntotal
        divv(i) = 0.e0
        dedt(i) = 0.e0
   10 continue

c     the velocity divergence of every particle
      do 30 k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        dvdw = 0.e0
        do 20 d = 1, dim
          dvdw = dvdw + (vx(d,j) - vx(d,i))*dwdx(d,k)
   20   continue
        divv(i) = divv(i) + mass(j)*dvdw/rho(j)
        divv(j) = divv(j) + mass(i)*dvdw/rho(i)
   30 continue

c     the heat each pair exchanges
      do 50 k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        hij = (hsml(i) + hsml(j))/2.
        rhoij = 0.5e0*(rho(i) + rho(j))
        r2 = 0.e0
        xdw = 0.e0
        do 40 d = 1, dim
          sep = x(d,i) - x(d,j)
          r2 = r2 + sep*sep
          xdw = xdw + sep*dwdx(d,k)
   40   continue
        qi = g1*hsml(i)*c(i) + g2*hsml(i)**2*(abs(divv(i)) - divv(i))
        qj = g1*hsml(j)*c(j) + g2*hsml(j)**2*(abs(divv(j)) - divv(j))
        qij = 0.5e0*(qi + qj)
        fac = qij/(rhoij*(r2 + 0.01*hij**2))*xdw
        dedt(i) = dedt(i) + mass(j)*fac*(u(i) - u(j))
        dedt(j) = dedt(j) + mass(i)*fac*(u(j) - u(i))
   50 continue

c     the sums above hold half of the exchange: double them
      do 60 i = 1, ntotal
        dedt(i) = 2.e0*dedt(i)
   60 continue

      end

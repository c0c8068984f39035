      subroutine art_visc(ntotal, hsml, mass, x, vx, niac, rho, c,
     &                    pair_i, pair_j, w, dwdx, dvxdt, dedt)
c-----------------------------------------------------------------------
c     Monaghan's artificial viscosity for approaching pairs:
c       mu_ij = h_ij v_ij.x_ij / (r_ij**2 + (etq h_ij)**2)
c       PI_ij = (beta mu_ij - alpha c_ij) mu_ij / rho_ij
c     (bars: means of the pair), with its heating.
c     ntotal -- number of particles                                (in)
c     hsml   -- smoothing lengths                                  (in)
c     mass   -- masses                                             (in)
c     x      -- positions                                          (in)
c     vx     -- velocities                                         (in)
c     niac   -- number of pairs                                    (in)
c     rho    -- densities                                          (in)
c     c      -- sound speeds                                       (in)
c     pair_i, pair_j -- the pairs                                  (in)
c     w      -- kernel of each pair (not used)                     (in)
c     dwdx   -- kernel gradient of each pair                       (in)
c     dvxdt  -- acceleration                                      (out)
c     dedt   -- heating rate                                      (out)
c-----------------------------------------------------------------------
      implicit none
      include 'param.inc'
      integer ntotal, niac, pair_i(max_interaction),
     &        pair_j(max_interaction)
      double precision hsml(maxn), mass(maxn), x(dim,maxn),
     &        vx(dim,maxn), rho(maxn), c(maxn), w(max_interaction),
     &        dwdx(dim,max_interaction), dvxdt(dim,maxn), dedt(maxn)
      integer i, j, k, d
      double precision alpha, beta, etq
c     alpha: shear term, beta: bulk (von Neumann-Richtmyer) term,
c     etq: keeps the denominator away from zero
      parameter (alpha = 1.e0, beta = 1.e0, etq = 0.1e0)
      double precision hij, vdotx, r2, sep, dv(dim), mu, cij, rhoij,
     &        visc_pi, f

      do 10 i = 1, ntotal
        do 5 d = 1, dim
          dvxdt(d,i) = 0.e0
    5   continue
        dedt(i) = 0.e0
   10 continue

      do 40 k = 1, niac
        i = pair_i(k)
        j = pair_j(k)
        hij = (hsml(i) + hsml(j))/2.
        vdotx = 0.e0
        r2 = 0.e0
        do 20 d = 1, dim
          dv(d) = vx(d,i) - vx(d,j)
          sep = x(d,i) - x(d,j)
          vdotx = vdotx + dv(d)*sep
          r2 = r2 + sep*sep
   20   continue
        if (vdotx .lt. 0.e0) then
          mu = hij*vdotx/(r2 + hij*hij*etq*etq)
          cij = 0.5e0*(c(i) + c(j))
          rhoij = 0.5e0*(rho(i) + rho(j))
          visc_pi = (beta*mu - alpha*cij)*mu/rhoij
          do 30 d = 1, dim
            f = -visc_pi*dwdx(d,k)
            dvxdt(d,i) = dvxdt(d,i) + mass(j)*f
            dvxdt(d,j) = dvxdt(d,j) - mass(i)*f
c           the heating goes to both particles, one component at a time
            dedt(i) = dedt(i) - mass(j)*dv(d)*f
            dedt(j) = dedt(j) - mass(i)*dv(d)*f
   30     continue
        endif
   40 continue

c     each pair was counted for both of its particles: halve
      do 50 i = 1, ntotal
        dedt(i) = 0.5e0*dedt(i)
   50 continue

      end
